// Headless test of the viewer: runs the tools on a mesh, serves viewer/ on
// localhost, opens the outputs in Debian's Chromium (through playwright-core)
// the way a user does (the "Open files" input), and fails if the page logs an
// error, a view or the image panel is blank, or what the page rebuilt differs
// from the tools' own outputs. Exit 77 (ctest: skipped) with the reason when
// Chromium, Node 20 or the vendored three.js is missing.
//
//   node viewer/test/render.mjs --bin build/bin --work DIR [--mesh M.obj] [--screenshots DIR]
//
// --mesh: the input (default: ism-genmesh blob, 3000 faces); --screenshots:
// also write viewer-gim.png and viewer-semireg.png there (docs/).
// --reuse yes: the tools' outputs of an earlier run in --work are kept.
import { spawnSync } from 'node:child_process';
import { existsSync, mkdirSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { createServer } from 'node:http';
import { basename, dirname, extname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const SKIP = 77;
const viewer = resolve(dirname(fileURLToPath(import.meta.url)), '..');
const args = Object.fromEntries(
  process.argv.slice(2).reduce((pairs, a, i, all) => (a.startsWith('--') ? [...pairs, [a.slice(2), all[i + 1]]] : pairs), []),
);
const chromiumPath = process.env.CHROMIUM ?? '/usr/bin/chromium';

function skip(reason) {
  console.log(`viewer test skipped: ${reason}`);
  process.exit(SKIP);
}
if (Number(process.versions.node.split('.')[0]) < 20) skip(`Node ${process.versions.node} (needs 20 or later)`);
if (!existsSync(chromiumPath)) skip(`${chromiumPath} not found (Debian package chromium; scripts/install-deps.sh installs it)`);
if (!existsSync(join(viewer, 'vendor/three/build/three.module.js')))
  skip('viewer/vendor/three missing (run scripts/viewer-deps.sh)');
if (!existsSync(join(viewer, 'node_modules/playwright-core')))
  skip('viewer/node_modules/playwright-core missing (run scripts/viewer-deps.sh)');
const { chromium } = await import('playwright-core');

const bin = resolve(args.bin ?? 'build/bin');
const work = resolve(args.work ?? mkdtempSync('/tmp/ism-viewer-'));
// --reuse yes: keep the tools' outputs of an earlier run in --work.
const reuse = args.reuse === 'yes' && existsSync(join(work, 'semireg'));
if (!reuse) rmSync(work, { recursive: true, force: true });
mkdirSync(work, { recursive: true });
const failures = [];
let checks = 0;
function check(ok, what) {
  ++checks;
  if (!ok) failures.push(what);
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
}

function run(tool, ...toolArgs) {
  if (reuse && tool !== 'ism-genmesh') return;
  const start = Date.now();
  const r = spawnSync(join(bin, tool), [...toolArgs, '-q'], { encoding: 'utf8' });
  if (r.status !== 0) throw new Error(`${tool} ${toolArgs.join(' ')}: ${r.stderr || r.error}`);
  console.log(`ran  ${tool} ${basename(toolArgs[0])} (${((Date.now() - start) / 1000).toFixed(1)} s)`);
}

// ---- the tools' outputs ----------------------------------------------------

const input = args.mesh ? resolve(args.mesh) : join(work, 'blob.obj');
if (!args.mesh) run('ism-genmesh', 'blob', '--faces', '3000', '-o', input);
const stem = basename(input, extname(input));
const gim = join(work, 'gim'), semireg = join(work, 'semireg'), morph = join(work, 'morph');
for (const d of [gim, semireg, morph]) mkdirSync(d, { recursive: true });
const size = args.screenshots ? '129' : '65';
run('gim-remesh', input, '-o', join(gim, `${stem}.exr`), '--size', size, '--inverse-weight', '0.1',
  '--mesh', join(gim, `${stem}_remesh.obj`), '--dump-patches', join(gim, `${stem}_patches.ply`),
  '--report', join(gim, `${stem}.json`));
run('semireg', input, '-o', join(semireg, `${stem}_sr.obj`), '--base-size', '60', '--levels', '3',
  '--report', join(semireg, `${stem}_sr.json`));

function readOBJ(path) {
  const v = [], f = [];
  for (const line of readFileSync(path, 'utf8').split('\n')) {
    const p = line.trim().split(/\s+/);
    if (p[0] === 'v') v.push(+p[1], +p[2], +p[3]);
    if (p[0] === 'f') f.push(...p.slice(1).map((t) => parseInt(t, 10) - 1));
  }
  return { v, f };
}

// A morph pair: the input and a Laplacian-smoothed copy (same vertex and face lists).
{
  const { v, f } = readOBJ(input);
  const neighbours = Array.from({ length: v.length / 3 }, () => new Set());
  for (let t = 0; t < f.length; t += 3)
    for (let k = 0; k < 3; ++k) neighbours[f[t + k]].add(f[t + ((k + 1) % 3)]).add(f[t + ((k + 2) % 3)]);
  let s = v.slice();
  for (let it = 0; it < 20; ++it) {
    const next = s.slice();
    neighbours.forEach((ns, i) => {
      for (let k = 0; k < 3; ++k) {
        let sum = 0;
        for (const j of ns) sum += s[3 * j + k];
        next[3 * i + k] = 0.5 * s[3 * i + k] + (0.5 * sum) / ns.size;
      }
    });
    s = next;
  }
  const write = (path, pos) => {
    let text = '';
    for (let i = 0; i < pos.length; i += 3) text += `v ${pos[i]} ${pos[i + 1]} ${pos[i + 2]}\n`;
    for (let t = 0; t < f.length; t += 3) text += `f ${f[t] + 1} ${f[t + 1] + 1} ${f[t + 2] + 1}\n`;
    writeFileSync(path, text);
  };
  write(join(morph, `${stem}_on_A.obj`), v);
  write(join(morph, `${stem}_on_B.obj`), s);
}

// ---- the page --------------------------------------------------------------

const TYPES = { '.html': 'text/html', '.js': 'text/javascript', '.mjs': 'text/javascript', '.css': 'text/css' };
const server = createServer((req, res) => {
  const path = resolve(viewer, '.' + decodeURIComponent(new URL(req.url, 'http://x').pathname));
  if (!path.startsWith(viewer) || !existsSync(path) || path.includes('node_modules')) {
    res.writeHead(404).end();
    return;
  }
  const file = path.endsWith('/') || !extname(path) ? join(path, 'index.html') : path;
  res.writeHead(200, { 'content-type': TYPES[extname(file)] ?? 'application/octet-stream' });
  res.end(readFileSync(file));
});
await new Promise((ok) => server.listen(0, '127.0.0.1', ok));
const url = `http://127.0.0.1:${server.address().port}/index.html`;

const userDataDir = mkdtempSync(join(work, 'chromium-'));
const context = await chromium.launchPersistentContext(userDataDir, {
  executablePath: chromiumPath,
  headless: true,
  viewport: { width: 1280, height: 640 },
  args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking',
    '--disable-component-update', '--disable-sync', '--enable-unsafe-swiftshader'],
});
const errors = [];
const page = context.pages()[0] ?? (await context.newPage());
page.on('console', (m) => m.type() === 'error' && errors.push(`console: ${m.text()}`));
page.on('pageerror', (e) => errors.push(`page error: ${e.message}`));
page.on('requestfailed', (r) => errors.push(`request failed: ${r.url()}`));

// Two animation frames: a render the page asked for has happened.
const nextFrames = () =>
  page.evaluate(() => new Promise((ok) => requestAnimationFrame(() => requestAnimationFrame(ok))));

async function open(files) {
  await page.goto(url);
  await page.waitForFunction(() => window.ismViewer !== undefined);
  await page.setInputFiles('#open-files', files);
  await page.waitForFunction(() => window.ismViewer.state.loads === 1);
  await nextFrames();
  return page.evaluate(() => window.ismViewer.summary());
}

// Not blank: the share of pixels that differ from the background, and how
// many distinct grey levels there are (shading, not a flat fill).
async function pixelStats(selector) {
  const png = (await page.locator(selector).screenshot()).toString('base64');
  return page.evaluate(async (data) => {
    const img = new Image();
    img.src = `data:image/png;base64,${data}`;
    await img.decode();
    const c = document.createElement('canvas');
    c.width = img.width;
    c.height = img.height;
    const ctx = c.getContext('2d');
    ctx.drawImage(img, 0, 0);
    const d = ctx.getImageData(0, 0, c.width, c.height).data;
    // The background: the commonest colour.
    const counts = new Map();
    for (let p = 0; p < d.length; p += 4) {
      const key = (d[p] << 16) | (d[p + 1] << 8) | d[p + 2];
      counts.set(key, (counts.get(key) ?? 0) + 1);
    }
    const top = [...counts.entries()].reduce((a, b) => (b[1] > a[1] ? b : a))[0];
    const bg = [top >> 16, (top >> 8) & 255, top & 255];
    let differ = 0;
    const levels = new Set();
    for (let p = 0; p < d.length; p += 4) {
      if (Math.abs(d[p] - bg[0]) + Math.abs(d[p + 1] - bg[1]) + Math.abs(d[p + 2] - bg[2]) > 24) ++differ;
      levels.add(`${d[p] >> 3},${d[p + 1] >> 3},${d[p + 2] >> 3}`);
    }
    return { width: c.width, height: c.height, covered: differ / (d.length / 4), colours: levels.size };
  }, png);
}

let shots = 0;
async function expectDrawn(selector, what, minCovered = 0.03) {
  await page.locator(selector).screenshot({ path: join(work, `step-${++shots}.png`) });
  const s = await pixelStats(selector);
  check(s.covered >= minCovered && s.colours >= 20,
    `${what} is drawn (${s.width}x${s.height}: ${(100 * s.covered).toFixed(1)}% covered, ${s.colours} colours)`);
}

const near = (a, b) => a.length === b.length && a.every((x, i) => Math.abs(x - b[i]) <= 1e-6 * (1 + Math.abs(b[i])));

try {
  // A geometry image beside its input, with the report and the patches.
  const exr = `${stem}.exr`;
  let s = await open([input, join(gim, exr), join(gim, `${stem}_remesh.obj`), join(gim, `${stem}.json`),
    join(gim, `${stem}_patches.ply`)]);
  check(s.left === basename(input) && s.right === exr, `gim: input on the left, image on the right (${s.left} | ${s.right})`);
  check(s.imagePanel, 'gim: the image panel is shown');
  const kinds = Object.fromEntries(s.items.map((i) => [i.name, i.kind]));
  check(kinds[`${stem}_patches.ply`] === 'patches', 'gim: the patch dump is read as patches');
  const n = Number(size);
  const image = s.items.find((i) => i.name === exr);
  check(image.vertices === (n - 1) ** 2 + 2 && image.faces === 2 * (n - 1) ** 2,
    `gim: the image rebuilds into (n-1)^2+2 = ${image.vertices} vertices, 2(n-1)^2 = ${image.faces} faces`);
  // The page's mesh of the image is the tool's remesh: same vertices, same faces, same order.
  const remesh = readOBJ(join(gim, `${stem}_remesh.obj`));
  const pagePositions = await page.evaluate((name) => window.ismViewer.positions(name), exr);
  const pageIndices = await page.evaluate((name) => window.ismViewer.indices(name), exr);
  check(near(pagePositions, remesh.v), 'gim: rebuilt vertices equal the tool\'s --mesh OBJ');
  check(pageIndices.length === remesh.f.length && pageIndices.every((x, i) => x === remesh.f[i]),
    'gim: rebuilt faces equal the tool\'s --mesh OBJ (layout, diagonals, orientation)');
  await expectDrawn('#view-left canvas', 'gim: the input view');
  await expectDrawn('#view-right canvas', 'gim: the rebuilt mesh view');
  await expectDrawn('#image-canvas', 'gim: the geometry image', 0.5);
  if (args.screenshots) {
    mkdirSync(args.screenshots, { recursive: true });
    await page.check('#wireframe');
    await nextFrames();
    await page.screenshot({ path: join(args.screenshots, 'viewer-gim.png') });
    await page.uncheck('#wireframe');
  }
  // The patches in the left view instead of the input (the list's buttons).
  await page.locator('#file-list li', { hasText: `${stem}_patches.ply` }).getByRole('button', { name: 'left' }).click();
  await nextFrames();
  s = await page.evaluate(() => window.ismViewer.summary());
  check(s.left === `${stem}_patches.ply`, 'gim: the patches go to the left view');
  await expectDrawn('#view-left canvas', 'gim: the patches view');

  // A semi-regular remesh beside its input.
  s = await open([input, join(semireg, `${stem}_sr.obj`), join(semireg, `${stem}_sr.json`)]);
  check(s.left === basename(input) && s.right === `${stem}_sr.obj`, `semireg: input | remesh (${s.left} | ${s.right})`);
  check(!s.imagePanel, 'semireg: no image panel');
  await expectDrawn('#view-left canvas', 'semireg: the input view');
  await expectDrawn('#view-right canvas', 'semireg: the remesh view');
  if (args.screenshots) {
    await page.check('#wireframe');
    await nextFrames();
    await page.screenshot({ path: join(args.screenshots, 'viewer-semireg.png') });
  }

  // A morph between two meshes with one connectivity.
  s = await open([join(morph, `${stem}_on_A.obj`), join(morph, `${stem}_on_B.obj`)]);
  const morphItem = s.items.find((i) => i.kind === 'morph');
  check(morphItem && s.right === morphItem.name, `morph: the pair becomes a morph (${morphItem?.name})`);
  check(await page.isVisible('#morph-bar'), 'morph: the slider is shown');
  await page.evaluate(() => window.ismViewer.setMorph(0.5));
  const [a, b, m] = await page.evaluate((names) => names.map((x) => window.ismViewer.positions(x)),
    [`${stem}_on_A.obj`, `${stem}_on_B.obj`, morphItem.name]);
  check(near(m, a.map((x, i) => 0.5 * x + 0.5 * b[i])), 'morph: at 0.5 the mesh is halfway');
  await nextFrames();
  await expectDrawn('#view-right canvas', 'morph: the morph view');
} catch (e) {
  check(false, `the page went through every step (${e.message.split('\n')[0]})`);
} finally {
  await page.screenshot({ path: join(work, 'last.png') }).catch(() => {});
  await context.close();
  server.close();
}
for (const e of errors) console.log(`FAIL ${e}`);
check(errors.length === 0, `the page logged no error (${errors.length})`);
console.log(`viewer: ${checks - failures.length} passed, ${failures.length} failed`);
process.exit(failures.length ? 1 : 0);
