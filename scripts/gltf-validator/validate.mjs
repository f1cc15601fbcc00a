// node validate.mjs FILE.glb...: validates each file with the Khronos glTF
// validator and prints one JSON line per file (errors, warnings, infos,
// hints, and the messages of the errors and warnings). Exits 1 when a file
// has an error or cannot be read, 0 otherwise.
import { readFile } from 'node:fs/promises';
import validator from 'gltf-validator';

let failed = 0;
for (const file of process.argv.slice(2)) {
  try {
    const bytes = new Uint8Array(await readFile(file));
    const report = await validator.validateBytes(bytes, { uri: file, maxIssues: 100 });
    const issues = report.issues;
    const messages = issues.messages
      .filter((m) => m.severity <= 1)
      .map((m) => `${m.severity === 0 ? 'error' : 'warning'} ${m.code} ${m.pointer ?? ''}: ${m.message}`);
    console.log(JSON.stringify({
      file,
      errors: issues.numErrors,
      warnings: issues.numWarnings,
      infos: issues.numInfos,
      hints: issues.numHints,
      messages,
    }));
    if (issues.numErrors > 0) failed += 1;
  } catch (error) {
    console.log(JSON.stringify({ file, errors: 1, messages: [`cannot validate: ${error}`] }));
    failed += 1;
  }
}
process.exit(failed > 0 ? 1 : 0);
