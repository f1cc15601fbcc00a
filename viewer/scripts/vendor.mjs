// Copies the parts of three.js the viewer imports from node_modules/three
// into vendor/three/ (same layout, so the modules' relative imports hold),
// following each module's relative imports. vendor/ is not committed.
import { copyFileSync, mkdirSync, readFileSync, rmSync, existsSync } from 'node:fs';
import { dirname, join, relative, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const viewer = resolve(dirname(fileURLToPath(import.meta.url)), '..');
const source = join(viewer, 'node_modules', 'three');
const target = join(viewer, 'vendor', 'three');
const entries = [
  'build/three.module.js',
  'examples/jsm/controls/OrbitControls.js',
  'examples/jsm/loaders/EXRLoader.js',
  'examples/jsm/loaders/OBJLoader.js',
  'examples/jsm/loaders/PLYLoader.js',
  'examples/jsm/loaders/STLLoader.js',
  'LICENSE',
];

if (!existsSync(join(source, 'package.json'))) {
  console.error(`vendor: ${source} not found (run npm ci in ${viewer})`);
  process.exit(1);
}
rmSync(target, { recursive: true, force: true });
const done = new Set();
const queue = entries.map((e) => join(source, e));
while (queue.length) {
  const file = queue.pop();
  if (done.has(file)) continue;
  done.add(file);
  const to = join(target, relative(source, file));
  mkdirSync(dirname(to), { recursive: true });
  copyFileSync(file, to);
  if (!file.endsWith('.js')) continue;
  // Static relative imports and re-exports: from './x.js' / import './x.js'.
  for (const m of readFileSync(file, 'utf8').matchAll(/(?:from|import)\s*['"](\.{1,2}\/[^'"]+)['"]/g))
    queue.push(resolve(dirname(file), m[1]));
}
const version = JSON.parse(readFileSync(join(source, 'package.json'), 'utf8')).version;
console.error(`vendor: three ${version}, ${done.size} files in ${relative(viewer, target)}/`);
