// The ism viewer: open an output folder or drop files; geometry images are
// shown as an image and as the rebuilt mesh, remeshes beside their inputs,
// patch dumps in their colours, and two meshes with one connectivity as a
// morph. Everything runs in the page; nothing is uploaded.
import * as THREE from 'three';
import { PLYLoader } from 'three/addons/loaders/PLYLoader.js';
import { STLLoader } from 'three/addons/loaders/STLLoader.js';
import { drawGeometryImage, octahedralMesh, readGeometryImage, torusMesh } from './geometry_image.js';
import { indexedGeometry, meshSize, parseOBJ, parseOFF } from './meshes.js';
import { blend, morphPairs } from './morph.js';
import { View } from './view.js';

const $ = (id) => document.getElementById(id);
const state = { items: [], left: null, right: null, messages: [], renders: 0, loads: 0 };

// ---- views -----------------------------------------------------------------

const camera = new THREE.PerspectiveCamera(35, 1, 1e-3, 1e3);
const target = new THREE.Vector3();
let frame = 0;
const requestRender = () => {
  if (!frame) frame = requestAnimationFrame(renderNow);
};
const views = { left: new View($('view-left'), camera, target, requestRender),
                right: new View($('view-right'), camera, target, requestRender) };

function renderNow() {
  frame = 0;
  const { clientWidth: w, clientHeight: h } = $('view-left');
  camera.aspect = w > 0 && h > 0 ? w / h : 1;
  camera.updateProjectionMatrix();
  for (const v of Object.values(views)) {
    v.resize();
    v.render();
  }
  ++state.renders;
}
new ResizeObserver(requestRender).observe($('views'));

// Both views framed together: the union of what they show, seen from the front-right.
function frameViews() {
  const spheres = Object.values(views).map((v) => v.bounds()).filter(Boolean);
  if (!spheres.length) return;
  const box = new THREE.Box3();
  for (const s of spheres) box.union(new THREE.Sphere(s.center, s.radius).getBoundingBox(new THREE.Box3()));
  const sphere = box.getBoundingSphere(new THREE.Sphere());
  const distance = (1.15 * sphere.radius) / Math.sin(THREE.MathUtils.degToRad(camera.fov / 2));
  target.copy(sphere.center);
  camera.position.copy(sphere.center).add(new THREE.Vector3(0.35, 0.25, 1).normalize().multiplyScalar(distance));
  camera.near = distance / 100;
  camera.far = distance * 10;
  camera.lookAt(target);
  for (const v of Object.values(views)) v.controls.update();
}

// ---- items -----------------------------------------------------------------

const KIND_LABEL = { mesh: 'mesh', image: 'geometry image', patches: 'patches', morph: 'morph' };

function describe(item) {
  const { vertices, faces } = meshSize(item.geometry);
  let text = `${KIND_LABEL[item.kind]}, ${vertices} vertices, ${faces} faces`;
  if (item.kind === 'image') text = `${item.image.rows}×${item.image.cols} ${item.image.layout} ${text}`;
  return text;
}

function addItem(item) {
  item.id = state.items.length;
  state.items.push(item);
  return item;
}

async function loadFile(file, reports) {
  const name = file.webkitRelativePath || file.name;
  const lower = file.name.toLowerCase();
  const ext = lower.slice(lower.lastIndexOf('.') + 1);
  if (ext === 'json') {
    const report = JSON.parse(await file.text());
    if (report && typeof report.tool === 'string') reports.push({ name, report });
    return;
  }
  if (ext === 'exr') {
    const image = readGeometryImage(await file.arrayBuffer());
    if (!image.layout) {
      state.messages.push(`${name}: an EXR without the ism layout, skipped`);
      return;
    }
    const data = image.layout === 'torus' ? torusMesh(image) : octahedralMesh(image);
    addItem({ name, file: file.name, kind: 'image', image, data, geometry: indexedGeometry(data) });
  } else if (ext === 'obj' || ext === 'off') {
    const data = ext === 'obj' ? parseOBJ(await file.text()) : parseOFF(await file.text());
    if (!data.indices.length) throw new Error('no faces');
    addItem({ name, file: file.name, kind: 'mesh', data, geometry: indexedGeometry(data) });
  } else if (ext === 'ply') {
    const geometry = new PLYLoader().parse(await file.arrayBuffer());
    if (!geometry.index && !geometry.getAttribute('position').count) throw new Error('no faces');
    // `property double` gives float64 attributes, which WebGL cannot draw.
    for (const [key, attribute] of Object.entries(geometry.attributes))
      if (attribute.array instanceof Float64Array)
        geometry.setAttribute(key, new THREE.BufferAttribute(new Float32Array(attribute.array), attribute.itemSize));
    geometry.computeVertexNormals();
    const colored = !!geometry.getAttribute('color');
    addItem({ name, file: file.name, kind: colored ? 'patches' : 'mesh', colored, geometry });
  } else if (ext === 'stl') {
    const geometry = new STLLoader().parse(await file.arrayBuffer());
    geometry.computeVertexNormals();
    addItem({ name, file: file.name, kind: 'mesh', geometry });
  } else {
    state.messages.push(`${name}: not a mesh, geometry image or report, skipped`);
  }
}

function addMorphs(fresh) {
  const meshes = fresh.filter((i) => i.kind === 'mesh' && i.data);
  for (const { a, b, label } of morphPairs(meshes)) {
    const positions = a.data.positions.slice();
    const geometry = indexedGeometry({ positions, indices: a.data.indices });
    addItem({ name: `morph ${label}`, kind: 'morph', a, b, t: 0, geometry });
  }
}

function setMorph(item, t) {
  item.t = t;
  const position = item.geometry.getAttribute('position');
  blend(item.a.data.positions, item.b.data.positions, t, position.array);
  position.needsUpdate = true;
  item.geometry.computeVertexNormals();
  item.geometry.computeBoundingSphere();
}

// Where the fresh items go: a tool's input (named in its report) on the left,
// its result on the right: the geometry image, else a morph, else a remesh,
// else the patches.
function arrange(fresh, reports) {
  const inputs = new Set(reports.flatMap(({ report }) =>
    (report.inputs ?? []).map((i) => String(i.file ?? '').split('/').pop())));
  const input = fresh.find((i) => i.kind === 'mesh' && inputs.has(i.file));
  const rank = { image: 0, morph: 1, mesh: 2, patches: 3 };
  const results = fresh.filter((i) => i !== input).sort((a, b) => rank[a.kind] - rank[b.kind]);
  const right = results[0] ?? null;
  const left = input ?? results.find((i) => i !== right && i.kind !== 'morph') ?? null;
  if (right || left) {
    state.right = right ?? left;
    state.left = right ? left : null;
  }
}

// ---- page ------------------------------------------------------------------

function showImagePanel() {
  const shown = [state.left, state.right].find((i) => i?.kind === 'image');
  $('image-panel').hidden = !shown;
  if (!shown) return;
  drawGeometryImage(shown.image, $('image-canvas'));
  $('image-caption').textContent =
    `${shown.name}: ${describe(shown)}. Colours: x y z as R G B over the bounding box; row 0 at the top.`;
  $('image-canvas').onmousemove = (e) => {
    const c = $('image-canvas'), r = c.getBoundingClientRect();
    const col = Math.floor(((e.clientX - r.left) / r.width) * shown.image.cols);
    const row = Math.floor(((e.clientY - r.top) / r.height) * shown.image.rows);
    if (row < 0 || col < 0 || row >= shown.image.rows || col >= shown.image.cols) return;
    const p = shown.image.pixels.subarray(3 * (row * shown.image.cols + col), 3 * (row * shown.image.cols + col) + 3);
    $('image-pixel').textContent = `pixel (${row}, ${col}): ${[...p].map((x) => x.toPrecision(6)).join(' ')}`;
  };
}

function updatePage() {
  const wireframe = $('wireframe').checked;
  for (const side of ['left', 'right']) {
    views[side].show(state[side], wireframe);
    const item = state[side];
    views[side].container.querySelector('.caption').textContent = item ? `${item.name} — ${describe(item)}` : '';
  }
  const morph = [state.right, state.left].find((i) => i?.kind === 'morph');
  $('morph-bar').hidden = !morph;
  if (morph) $('morph').value = String(Math.round(morph.t * 1000));
  showImagePanel();
  const list = $('file-list');
  list.replaceChildren();
  for (const item of state.items) {
    const li = document.createElement('li');
    li.innerHTML = '<div class="name"></div><div class="what"></div><div class="place"></div>';
    li.querySelector('.name').textContent = item.name;
    li.querySelector('.what').textContent = describe(item);
    for (const side of ['left', 'right']) {
      const b = document.createElement('button');
      b.textContent = side;
      b.className = state[side] === item ? 'on' : '';
      b.onclick = () => {
        state[side] = state[side] === item ? null : item;
        updatePage();
        frameViews();
      };
      li.querySelector('.place').append(b);
    }
    list.append(li);
  }
  $('status').textContent = state.messages.length ? state.messages.join(' · ') : $('status').dataset.hint;
  // One item: one view, the full width.
  views.left.container.hidden = !state.left && !!state.right;
  views.right.container.hidden = !state.right && !!state.left;
  requestRender();
}

/** Loads files (File objects), arranges what they hold, and renders. */
async function loadFiles(files) {
  state.messages = [];
  const before = state.items.length;
  const reports = [];
  const sorted = [...files].sort((a, b) => (a.webkitRelativePath || a.name).localeCompare(b.webkitRelativePath || b.name));
  for (const file of sorted) {
    try {
      await loadFile(file, reports);
    } catch (e) {
      state.messages.push(`${file.name}: ${e.message}`);
      console.error(`ism viewer: ${file.name}: ${e.message}`);
    }
  }
  const fresh = state.items.slice(before);
  addMorphs(fresh);
  arrange(state.items.slice(before), reports);
  updatePage();
  frameViews();
  ++state.loads;
  requestRender();
}

// Dropped folders are walked; dropped files taken as they are.
async function droppedFiles(dataTransfer) {
  const entries = [...dataTransfer.items].map((i) => i.webkitGetAsEntry?.()).filter(Boolean);
  if (!entries.length) return [...dataTransfer.files];
  const files = [];
  const walk = async (entry) => {
    if (entry.isFile) files.push(await new Promise((ok, fail) => entry.file(ok, fail)));
    else if (entry.isDirectory) {
      const reader = entry.createReader();
      for (;;) {
        const batch = await new Promise((ok, fail) => reader.readEntries(ok, fail));
        if (!batch.length) break;
        for (const e of batch) await walk(e);
      }
    }
  };
  for (const e of entries) await walk(e);
  return files;
}

$('open-files').onchange = (e) => loadFiles(e.target.files);
$('open-folder').onchange = (e) => loadFiles(e.target.files);
$('wireframe').onchange = updatePage;
$('morph').oninput = (e) => {
  const morph = [state.right, state.left].find((i) => i?.kind === 'morph');
  if (!morph) return;
  setMorph(morph, Number(e.target.value) / 1000);
  $('morph-value').textContent = morph.t.toFixed(2);
  requestRender();
};
document.addEventListener('dragover', (e) => {
  e.preventDefault();
  document.body.classList.add('dragging');
});
document.addEventListener('dragleave', () => document.body.classList.remove('dragging'));
document.addEventListener('drop', async (e) => {
  e.preventDefault();
  document.body.classList.remove('dragging');
  await loadFiles(await droppedFiles(e.dataTransfer));
});

// For scripts (the headless test): the state, and the rebuilt meshes' arrays.
window.ismViewer = {
  state,
  loadFiles,
  setMorph: (t) => {
    $('morph').value = String(Math.round(t * 1000));
    $('morph').dispatchEvent(new Event('input'));
  },
  summary: () => ({
    loads: state.loads,
    renders: state.renders,
    messages: state.messages,
    left: state.left?.name ?? null,
    right: state.right?.name ?? null,
    imagePanel: !$('image-panel').hidden,
    items: state.items.map((i) => ({ name: i.name, kind: i.kind, ...meshSize(i.geometry) })),
  }),
  positions: (name) => Array.from(state.items.find((i) => i.name === name).geometry.getAttribute('position').array),
  indices: (name) => Array.from(state.items.find((i) => i.name === name).geometry.index?.array ?? []),
};
updatePage();
