// Indexed triangle meshes from OBJ and OFF text, kept with the file's own
// vertex and face lists (three's OBJLoader expands faces into corners, which
// loses the connectivity a morph between two files needs). Polygons are
// split into fans, as the ism tools do when they read.
import * as THREE from 'three';

function fan(polygon, out) {
  for (let k = 1; k + 1 < polygon.length; ++k) out.push(polygon[0], polygon[k], polygon[k + 1]);
}

/** OBJ `v` and `f` lines (indices 1-based or negative, `f a/b/c` forms). */
export function parseOBJ(text) {
  const positions = [];
  const indices = [];
  let line = 0;
  for (const raw of text.split('\n')) {
    ++line;
    const s = raw.trim();
    if (s.startsWith('v ')) {
      const p = s.split(/\s+/);
      positions.push(+p[1], +p[2], +p[3]);
    } else if (s.startsWith('f ')) {
      const n = positions.length / 3;
      const polygon = s.split(/\s+/).slice(1).map((t) => {
        const i = parseInt(t, 10);
        return i < 0 ? n + i : i - 1;
      });
      if (polygon.some((i) => !(i >= 0 && i < n)))
        throw new Error(`line ${line}: face index out of range`);
      fan(polygon, indices);
    }
  }
  if (positions.some((x) => !Number.isFinite(x))) throw new Error('non-finite coordinates');
  return { positions: new Float32Array(positions), indices: new Uint32Array(indices) };
}

/** OFF: header, counts, vertices, then faces as "k i0 i1 ...". */
export function parseOFF(text) {
  const tokens = text.replace(/#[^\n]*/g, '').split(/\s+/).filter((t) => t.length);
  if (!/^N?C?OFF$/.test(tokens[0] ?? '')) throw new Error('not an OFF file');
  let at = 1;
  const nv = +tokens[at++], nf = +tokens[at++];
  ++at;  // edges
  const positions = new Float32Array(3 * nv);
  for (let v = 0; v < nv; ++v) {
    for (let k = 0; k < 3; ++k) positions[3 * v + k] = +tokens[at++];
    if (tokens[0].includes('C')) at += 3;
  }
  const indices = [];
  for (let f = 0; f < nf; ++f) {
    const k = +tokens[at++];
    const polygon = tokens.slice(at, at + k).map(Number);
    at += k;
    if (polygon.some((i) => !(i >= 0 && i < nv))) throw new Error(`face ${f}: index out of range`);
    fan(polygon, indices);
  }
  return { positions, indices: new Uint32Array(indices) };
}

/** A BufferGeometry with smooth normals from positions and triangle indices. */
export function indexedGeometry({ positions, indices }) {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  g.setIndex(new THREE.BufferAttribute(indices, 1));
  g.computeVertexNormals();
  g.computeBoundingSphere();
  return g;
}

/** Vertex and face counts of a geometry (indexed or a triangle soup). */
export function meshSize(geometry) {
  const vertices = geometry.getAttribute('position').count;
  const faces = (geometry.index ? geometry.index.count : vertices) / 3;
  return { vertices, faces };
}
