// What is drawn while the camera moves (scene.js's moving state): a model of many triangles
// is replaced by a coarser one, so that a software renderer keeps up with the motion. A mesh
// is simplified by vertex clustering (Rossignac and Borrel 1993): the vertices in each cell of
// a grid over its bounds merge into their mean, triangles whose corners merge vanish.
import * as THREE from 'three';

/// Meshes with more triangles than this are drawn through a proxy while the camera moves.
export const MOTION_TRIANGLES = 20000;

/// Clusters the vertices of @a geometry (indexed, with positions) on a grid of @a cells along
/// its longest side; returns the clustered positions, normals and indices.
function cluster(positions, index, box, cells) {
  const size = box.getSize(new THREE.Vector3());
  const step = Math.max(size.x, size.y, size.z) / cells || 1;
  const dims = [0, 1, 2].map((a) => Math.max(1, Math.ceil(size.getComponent(a) / step) + 1));
  const cellOf = new Int32Array(dims[0] * dims[1] * dims[2]).fill(-1);
  const vertexCluster = new Int32Array(positions.length / 3);
  const sums = [];
  for (let v = 0; v < vertexCluster.length; ++v) {
    const at = [0, 1, 2].map((a) => Math.min(dims[a] - 1, Math.floor((positions[3 * v + a] - box.min.getComponent(a)) / step)));
    const key = at[0] + dims[0] * (at[1] + dims[1] * at[2]);
    if (cellOf[key] < 0) {
      cellOf[key] = sums.length / 4;
      sums.push(0, 0, 0, 0);
    }
    const c = cellOf[key];
    vertexCluster[v] = c;
    for (let a = 0; a < 3; ++a) sums[4 * c + a] += positions[3 * v + a];
    sums[4 * c + 3] += 1;
  }
  const triangles = [];
  for (let t = 0; t < index.length; t += 3) {
    const a = vertexCluster[index[t]], b = vertexCluster[index[t + 1]], c = vertexCluster[index[t + 2]];
    if (a !== b && b !== c && a !== c) triangles.push(a, b, c);
  }
  const clusters = sums.length / 4;
  const merged = new Float32Array(3 * clusters);
  for (let c = 0; c < clusters; ++c) for (let a = 0; a < 3; ++a) merged[3 * c + a] = sums[4 * c + a] / sums[4 * c + 3];
  return { positions: merged, index: triangles };
}

/// A coarser stand-in for @a geometry of at most about MOTION_TRIANGLES triangles, or null when
/// it has no more than that already.
export function motionGeometry(geometry) {
  const index = geometry.index?.array;
  if (!index || index.length / 3 <= MOTION_TRIANGLES) return null;
  const positions = geometry.getAttribute('position').array;
  const box = geometry.boundingBox ?? new THREE.Box3().setFromBufferAttribute(geometry.getAttribute('position'));
  // A surface's triangles grow as the square of the grid's resolution: one trial, then the
  // resolution that should give the target, lowered again while it gives too many.
  let cells = 64;
  let result = cluster(positions, index, box, cells);
  cells = Math.max(4, Math.floor(cells * Math.sqrt(MOTION_TRIANGLES / Math.max(result.index.length / 3, 1))));
  result = cluster(positions, index, box, cells);
  while (result.index.length / 3 > MOTION_TRIANGLES && cells > 4) result = cluster(positions, index, box, (cells = Math.floor(cells * 0.85)));
  const proxy = new THREE.BufferGeometry();
  proxy.setAttribute('position', new THREE.BufferAttribute(result.positions, 3));
  proxy.setIndex(result.index);
  proxy.computeVertexNormals();
  return proxy;
}
