#!/usr/bin/env bash
# ism-batch gim-remesh (129², one map variant: inverse weight 0.1, and the
# remesh as OBJ; half the work of the defaults) over every closed genus-0
# model of ../shared/models, and torus.obj, which gim-remesh refuses (genus 1), in
# two shards:
#   BATCH_ENGINE=parallel  (default) GNU parallel, two jobs on this machine;
#   BATCH_ENGINE=slurm     a job array on a running Slurm (sbatch --wait
#                          --array=0-1; scripts/slurm-single-node.sh brings
#                          one up on this machine and runs this).
# Checks the results (every model's line once, failures with the tool's error
# line, nothing partial on disk) and prints them as a Markdown table; needs
# python3. BATCH_OUT=DIR keeps the outputs (default: a scratch folder).
#   bench/batch.sh > docs/results-batch.md
source "$(dirname "$0")/common.sh"
out="${BATCH_OUT:-$work/out}"
engine="${BATCH_ENGINE:-parallel}"
list="$out.list"
mkdir -p "$(dirname "$out")"
python3 "$root/bench/batch_results.py" list "$models_dir" > "$list"
tool_options=(--size 129 --inverse-weight 0.1 --mesh '{name}_remesh.obj')
start=$(date +%s)
case "$engine" in
  parallel)
    parallel --will-cite --jobs 2 "$bin/ism-batch" gim-remesh --inputs "$list" --out "$out" \
      --shard {}/2 -- "${tool_options[@]}" ::: 0 1
    ;;
  slurm)
    # Each array task is one shard; the command is a shell line, so quote it.
    job="$(printf '%q ' "$bin/ism-batch" gim-remesh --inputs "$list" --out "$out")"
    job+='--shard "$SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT" -- '
    job+="$(printf '%q ' "${tool_options[@]}")"
    sbatch --wait --array=0-1 --cpus-per-task=1 --job-name=ism-batch \
      --output="$out.slurm-%A_%a.log" --wrap "$job" >&2
    cat "$out".slurm-*.log >&2
    ;;
  *)
    echo "bench/batch.sh: BATCH_ENGINE must be parallel or slurm, not $engine" >&2
    exit 2
    ;;
esac
seconds=$(($(date +%s) - start))
python3 "$root/bench/batch_results.py" check "$list" "$out"
echo "ism-batch gim-remesh ${tool_options[*]}, two shards through $engine, $(nproc) cores; wall time $seconds s. Commit $commit."
echo
python3 "$root/bench/batch_results.py" table "$out"
