// Geometry images written by the ism tools (README "Geometry image layout"
// and "Torus grids"): float RGB OpenEXR, R G B = x y z, tagged ism:layout.
import * as THREE from 'three';
import { EXRLoader } from 'three/addons/loaders/EXRLoader.js';

/**
 * Reads an EXR into { rows, cols, layout, pixels, alpha }: pixels row-major
 * with row 0 at the top of the image, 3 floats each. layout is the file's
 * ism:layout ('octahedral', 'torus'), or 'octahedral' for an untagged square
 * image of side 2^k+1, else null (shown as an image only). alpha: channel A
 * in the same order (gim-remesh of an open surface: 1 on the surface, 0 on a
 * cap), or null when the file has none.
 */
export function readGeometryImage(buffer) {
  const loader = new EXRLoader().setDataType(THREE.FloatType);
  const exr = loader.parse(buffer);
  const rows = exr.height, cols = exr.width;
  // EXRLoader stores the bottom row first, RGBA.
  const pixels = new Float32Array(rows * cols * 3);
  const hasAlpha = (exr.header?.channels ?? []).some((c) => c.name === 'A');
  const alpha = hasAlpha ? new Float32Array(rows * cols) : null;
  for (let i = 0; i < rows; ++i)
    for (let j = 0; j < cols; ++j) {
      const from = 4 * ((rows - 1 - i) * cols + j);
      for (let k = 0; k < 3; ++k) pixels[3 * (i * cols + j) + k] = exr.data[from + k];
      if (alpha) alpha[i * cols + j] = exr.data[from + 3];
    }
  let layout = exr.header?.['ism:layout'] ?? null;
  const n = rows;
  if (!layout && rows === cols && n >= 3 && ((n - 1) & (n - 2)) === 0) layout = 'octahedral';
  if (layout === 'octahedral' && !(rows === cols && n >= 3 && ((n - 1) & (n - 2)) === 0))
    throw new Error(`octahedral image of ${rows}x${cols}: needs n x n with n = 2^k+1`);
  return { rows, cols, layout, pixels, alpha };
}

// The canonical pixel of a pixel's mirror orbit on the square's boundary
// (each side mirrored about its midpoint, the four corners one point): the
// first of the orbit in row-major order.
function canonicalPixel(n, i, j) {
  const last = n - 1;
  if ((i === 0 || i === last) && (j === 0 || j === last)) return [0, 0];
  if (i === 0 || i === last) return [i, Math.min(j, last - j)];
  if (j === 0 || j === last) return [Math.min(i, last - i), j];
  return [i, j];
}

/**
 * The mesh of an octahedral image, as read_geometry_image_mesh() builds it:
 * one vertex per pixel orbit, numbered in row-major order of the canonical
 * pixels, (n-1)^2+2 in all; each grid cell split along the diagonal parallel
 * to its quadrant's octahedron edge, counter-clockwise seen from outside.
 * With alpha, as image_to_surface_mesh(): only the triangles with alpha 1 at
 * all three corners, and the vertices they use (in the same order).
 */
export function octahedralMesh({ rows: n, pixels, alpha = null }) {
  const vertex = new Int32Array(n * n);
  const positions = new Float32Array(3 * ((n - 1) * (n - 1) + 2));
  let next = 0;
  for (let i = 0; i < n; ++i)
    for (let j = 0; j < n; ++j) {
      const [r, c] = canonicalPixel(n, i, j);
      if (r === i && c === j) {
        positions.set(pixels.subarray(3 * (i * n + j), 3 * (i * n + j) + 3), 3 * next);
        vertex[i * n + j] = next++;
      } else {
        vertex[i * n + j] = vertex[r * n + c];
      }
    }
  const m = (n - 1) / 2;
  const indices = new Uint32Array(6 * (n - 1) * (n - 1));
  let f = 0;
  const put = (...corners) => {
    if (alpha && corners.some(([i, j]) => alpha[i * n + j] < 0.5)) return;
    for (const [i, j] of corners) indices[f++] = vertex[i * n + j];
  };
  for (let i = 0; i + 1 < n; ++i)
    for (let j = 0; j + 1 < n; ++j) {
      const tl = [i, j], tr = [i, j + 1], bl = [i + 1, j], br = [i + 1, j + 1];
      if (j >= m === i < m) put(tl, bl, br), put(tl, br, tr);
      else put(bl, br, tr), put(bl, tr, tl);
    }
  if (!alpha) return { positions, indices };
  // Drop the vertices only cap triangles used; the others keep their order.
  const used = new Int32Array(next).fill(-1);
  for (let k = 0; k < f; ++k) used[indices[k]] = 0;
  let kept = 0;
  const surface = new Float32Array(3 * next);
  for (let v = 0; v < next; ++v)
    if (used[v] === 0) {
      surface.set(positions.subarray(3 * v, 3 * v + 3), 3 * kept);
      used[v] = kept++;
    }
  const faces = indices.slice(0, f).map((v) => used[v]);
  return { positions: surface.slice(0, 3 * kept), indices: faces };
}

/**
 * The grid of a periodic torus image (README "Torus grids"): vertex j*U+i is
 * pixel (row j, column i); quad (j, i) has corners (j,i) (j,i+1) (j+1,i+1)
 * (j+1,i) modulo the size, split along its shorter diagonal.
 */
export function torusMesh({ rows: V, cols: U, pixels }) {
  const positions = pixels.slice();
  const indices = new Uint32Array(6 * U * V);
  const id = (j, i) => ((j + V) % V) * U + ((i + U) % U);
  const dist2 = (a, b) => {
    let s = 0;
    for (let k = 0; k < 3; ++k) s += (positions[3 * a + k] - positions[3 * b + k]) ** 2;
    return s;
  };
  let f = 0;
  for (let j = 0; j < V; ++j)
    for (let i = 0; i < U; ++i) {
      const a = id(j, i), b = id(j, i + 1), c = id(j + 1, i + 1), d = id(j + 1, i);
      const tri = dist2(a, c) <= dist2(b, d) ? [a, b, c, a, c, d] : [a, b, d, b, c, d];
      indices.set(tri, f);
      f += 6;
    }
  return { positions, indices };
}

/**
 * Draws the image into a canvas, one canvas pixel per image pixel: the
 * positions normalised to their bounding box as RGB (the tool's preview).
 */
export function drawGeometryImage({ rows, cols, pixels }, canvas) {
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (let p = 0; p < rows * cols; ++p)
    for (let k = 0; k < 3; ++k) {
      lo[k] = Math.min(lo[k], pixels[3 * p + k]);
      hi[k] = Math.max(hi[k], pixels[3 * p + k]);
    }
  canvas.width = cols;
  canvas.height = rows;
  const ctx = canvas.getContext('2d');
  const out = ctx.createImageData(cols, rows);
  for (let p = 0; p < rows * cols; ++p) {
    for (let k = 0; k < 3; ++k) {
      const extent = Math.max(hi[k] - lo[k], 1e-300);
      out.data[4 * p + k] = Math.round((255 * (pixels[3 * p + k] - lo[k])) / extent);
    }
    out.data[4 * p + 3] = 255;
  }
  ctx.putImageData(out, 0, 0);
}
