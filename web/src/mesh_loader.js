// GET /api/mesh: the server's binary buffers (positions, normals, indices) as a BufferGeometry.
import * as THREE from 'three';

/// Thrown when the full mesh has more triangles than the budget: its count, not its buffers.
/// estimated: the server did not make it (a grid read by region), the count is its estimate.
export class OverBudget extends Error {
  constructor(triangles, estimated = false) {
    super(`${triangles} triangles`);
    this.triangles = triangles;
    this.estimated = estimated;
  }
}

/// The query string of a mesh: level, method, iso, error, adaptivity.
export function meshQuery(params) {
  return new URLSearchParams(Object.entries(params).filter(([, value]) => value !== undefined)).toString();
}

async function errorText(response) {
  try {
    return (await response.json()).error;
  } catch {
    return response.statusText;
  }
}

/// @returns {geometry, triangles, vertices, seconds}
export async function fetchMesh(params, signal) {
  const response = await fetch(`/api/mesh?${meshQuery(params)}`, { signal });
  if (response.status === 413) {
    throw new OverBudget(Number(response.headers.get('X-Triangles')), response.headers.get('X-Estimated') === '1');
  }
  if (!response.ok) throw new Error(await errorText(response));
  const vertices = Number(response.headers.get('X-Vertices'));
  const triangles = Number(response.headers.get('X-Triangles'));
  const buffer = await response.arrayBuffer();
  if (buffer.byteLength !== 24 * vertices + 12 * triangles) throw new Error('mesh buffers: unexpected size');
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(buffer, 0, 3 * vertices), 3));
  geometry.setAttribute('normal', new THREE.BufferAttribute(new Float32Array(buffer, 12 * vertices, 3 * vertices), 3));
  geometry.setIndex(new THREE.BufferAttribute(new Uint32Array(buffer, 24 * vertices, 3 * triangles), 1));
  geometry.computeBoundingBox();
  return { geometry, triangles, vertices, seconds: Number(response.headers.get('X-Seconds')) };
}

export async function fetchJson(url, signal) {
  const response = await fetch(url, { signal });
  if (!response.ok) throw new Error(await errorText(response));
  return response.json();
}
