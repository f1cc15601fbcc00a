// Morphs between two meshes with the same vertex and face lists, such as the
// overlay pair PREFIX_on_A.obj / PREFIX_on_B.obj of a surface-to-surface map
// (each vertex of one is the other's vertex at the same index).

/** True when both index arrays are equal and the vertex counts match. */
export function sameConnectivity(a, b) {
  if (a.positions.length !== b.positions.length || a.indices.length !== b.indices.length)
    return false;
  for (let k = 0; k < a.indices.length; ++k) if (a.indices[k] !== b.indices[k]) return false;
  return true;
}

/**
 * Pairs among `meshes` ({name, data}) that can be morphed: first the
 * X_on_A / X_on_B pairs, then any two other meshes with equal connectivity.
 * Each mesh is in at most one pair.
 */
export function morphPairs(meshes) {
  const used = new Set();
  const pairs = [];
  const stem = (name) => name.replace(/\.[^.]*$/, '');
  const take = (a, b, label) => {
    used.add(a);
    used.add(b);
    pairs.push({ a, b, label });
  };
  for (const a of meshes) {
    const m = stem(a.name).match(/^(.*)_on_A$/);
    if (!m || used.has(a)) continue;
    const b = meshes.find((x) => stem(x.name) === `${m[1]}_on_B` && !used.has(x));
    if (b && sameConnectivity(a.data, b.data)) take(a, b, m[1]);
  }
  for (let i = 0; i < meshes.length; ++i)
    for (let j = i + 1; j < meshes.length; ++j) {
      const a = meshes[i], b = meshes[j];
      if (used.has(a) || used.has(b)) continue;
      if (sameConnectivity(a.data, b.data)) take(a, b, `${stem(a.name)} → ${stem(b.name)}`);
    }
  return pairs;
}

/** positions (1-t)·A + t·B into `out`. */
export function blend(a, b, t, out) {
  for (let k = 0; k < out.length; ++k) out[k] = (1 - t) * a[k] + t * b[k];
  return out;
}
