// Splat mode (GET /api/splats): the scan's splat hierarchy as oriented discs, lit like the
// mesh. The page sends its camera when it stops moving and the server answers with the
// nodes that view needs (by projected size, within the budget); while the camera moves the
// last answer stays on screen, so a view is refined each time the camera comes to rest.
// Close up, where the view asks for more detail than the finest splats hold and the mesh is
// cheaper (src/view/close_up.h), the server names a box: the page fetches the full mesh's
// triangles there (GET /api/mesh?level=region) and draws them instead of the splats inside it.
import * as THREE from 'three';
import { fetchMesh } from './mesh_loader.js';
import { MOTION_TRIANGLES } from './motion_proxy.js';

const SPLAT_COLOUR = 0xd9cbb0;  // the mesh's
const DISC_SEGMENTS = 8;
const SETTLE_MS = 250;           // the camera counts as still after this long without a change
export const SPLAT_BUDGET = 60000;
const PIXEL_SIZE = 3;            // refine while a disc spans more pixels than this
/// A close-up has at most the triangles the budget's discs would take.
export const CLOSE_UP_TRIANGLES = DISC_SEGMENTS * SPLAT_BUDGET;
/// While the camera moves, at most this many discs are drawn (every k-th, k times the area).
const MOTION_SPLATS = MOTION_TRIANGLES / DISC_SEGMENTS;

const DISC_VERTICES = DISC_SEGMENTS + 1;  // the centre, then the rim
const DISC_INDICES = 3 * DISC_SEGMENTS;
const RIM = Array.from({ length: DISC_SEGMENTS }, (_, k) => (2 * Math.PI * k) / DISC_SEGMENTS).map((a) => [Math.cos(a), Math.sin(a)]);

export class SplatLayer {
  /// @a handlers: onAsk() when a view is asked for, onShown(figures) when its answer is drawn
  /// ({ splats, kind ('preview': the topology preview, or 'fitted'), level, cutLevel, complete, treeNodes, seconds, ms, closeUp: null or { box,
  /// triangles, seconds } }), onError(error), meshParams() the mesh's method and parameters,
  /// onCloseUp(mesh or null) the close-up's triangles to draw (null: none).
  constructor(scene3d, handlers) {
    Object.assign(this, { scene3d, handlers });
    this.group = new THREE.Group();
    this.group.visible = false;
    scene3d.scene.add(this.group);
    this.material = new THREE.MeshStandardMaterial({ color: SPLAT_COLOUR, roughness: 0.6, metalness: 0.05, side: THREE.DoubleSide });
    // While moving: Lambert's shading, cheaper a fragment than the standard material's (SwiftShader
    // drew the motion's discs in 126 ms a frame instead of 191 ms, issue 30).
    this.motionMaterial = new THREE.MeshLambertMaterial({ color: SPLAT_COLOUR, side: THREE.DoubleSide });
    this.iso = undefined;
    scene3d.controls.addEventListener('change', () => this.cameraMoved());
  }

  get enabled() {
    return this.group.visible;
  }

  /// Shows splats at @a iso instead of the mesh (or stops).
  setEnabled(on, iso) {
    this.group.visible = on;
    this.iso = iso;
    if (on) this.refresh();
    this.scene3d.requestRender();
  }

  setIso(iso) {
    this.iso = iso;
    if (this.enabled) this.refresh();
  }

  setClipPlanes(planes) {
    this.material.clippingPlanes = planes;
    this.motionMaterial.clippingPlanes = planes;
    this.scene3d.requestRender();
  }

  cameraMoved() {
    if (!this.enabled) return;
    clearTimeout(this.settle);
    this.settle = setTimeout(() => this.refresh(), SETTLE_MS);
  }

  query(budget) {
    const camera = this.scene3d.camera;
    camera.updateMatrixWorld();
    const viewProjection = new THREE.Matrix4().multiplyMatrices(camera.projectionMatrix, camera.matrixWorldInverse);
    const height = this.scene3d.renderer.domElement.height;
    const focal = height / (2 * Math.tan(THREE.MathUtils.degToRad(camera.fov) / 2));
    const params = {
      vp: viewProjection.elements.map((v) => v.toPrecision(9)).join(','),
      eye: camera.position.toArray().map((v) => v.toPrecision(9)).join(','),
      focal: focal.toPrecision(9), pixel: PIXEL_SIZE, budget, closeup: CLOSE_UP_TRIANGLES,
    };
    if (this.iso !== undefined) params.iso = this.iso;
    return new URLSearchParams(params).toString();
  }

  /// Asks for the current view's splats; a newer request aborts an older one. The first after
  /// quickFirst(n) asks for n splats only, then the full budget's follow.
  async refresh() {
    this.abort?.abort();
    const abort = (this.abort = new AbortController());
    this.handlers.onAsk();
    const started = performance.now();
    const budget = this.firstBudget ?? SPLAT_BUDGET;
    this.firstBudget = undefined;
    try {
      const response = await fetch(`/api/splats?${this.query(budget)}`, { signal: abort.signal });
      if (!response.ok) throw new Error((await response.json()).error ?? response.statusText);
      const count = Number(response.headers.get('X-Splats'));
      const buffer = await response.arrayBuffer();
      if (buffer.byteLength !== 28 * count) throw new Error('splat buffers: unexpected size');
      this.show(new Float32Array(buffer), count);
      const box = response.headers.get('X-Closeup-Box');
      let closeUp = null;
      if (box) {
        // The splats stay on screen (all of them) until the triangles that replace some arrive.
        const mesh = await fetchMesh({ ...this.handlers.meshParams(), iso: this.iso, level: 'region', box }, abort.signal);
        if (abort !== this.abort) return;
        this.setShownCount(count - Number(response.headers.get('X-Closeup-Splats')));
        closeUp = { box, triangles: mesh.triangles, seconds: mesh.seconds, mesh };
      }
      this.handlers.onCloseUp(closeUp?.mesh ?? null);
      await this.scene3d.nextRender();
      if (abort !== this.abort) return;
      this.handlers.onShown({
        splats: this.count, kind: response.headers.get('X-Splat-Kind') ?? 'fitted', level: Number(response.headers.get('X-Level')), cutLevel: Number(response.headers.get('X-Cut-Level')), complete: response.headers.get('X-Complete') === '1',
        treeNodes: Number(response.headers.get('X-Tree-Nodes')), seconds: Number(response.headers.get('X-Seconds')),
        ms: performance.now() - started, closeUp: closeUp && { box, triangles: closeUp.triangles, seconds: closeUp.seconds },
      });
      // The full budget once the quick first picture is on screen: two animation frames later
      // (Chromium runs them once the previous frame is drawn). Asked at once, its 60,000 discs'
      // upload held the page's thread while SwiftShader still drew the first (the bench's
      // polling saw the first picture 1.4 to 2.7 s after the page had asked for it, issue 30).
      if (budget < SPLAT_BUDGET) {
        await new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve)));
        if (abort === this.abort) this.refresh();
      }
    } catch (error) {
      if (error.name === 'AbortError') return;
      this.handlers.onError(error);
    }
  }

  /// Compiles the discs' shader in the background, with a disc that is never drawn: the
  /// program is the one the first view's discs will use.
  precompile() {
    const probe = discMesh(new Float32Array([0, 0, 0, 0, 0, 1, 1]), 1, 1, this.material);
    probe.visible = false;  // compile() compiles hidden objects too
    this.group.add(probe);
    const done = () => {
      this.group.remove(probe);
      probe.geometry.dispose();
    };
    return this.scene3d.renderer.compileAsync(this.scene3d.scene, this.scene3d.camera).then(done, done);
  }

  /// The next view asks for @a budget splats (a quick first picture: fewer to select, send
  /// and draw), the one after it for the full budget.
  quickFirst(budget) {
    this.firstBudget = budget;
  }

  /// The first @a count discs drawn (the close-up's triangles replace the others).
  setShownCount(count) {
    this.count = count;
    this.mesh.geometry.setDrawRange(0, DISC_INDICES * count);
  }

  /// While @a moving, every k-th disc of those drawn, k times larger in area, so that at most
  /// MOTION_SPLATS are drawn.
  setMoving(moving) {
    this.dropMotion();
    if (this.mesh) this.mesh.visible = true;
    if (!moving || !this.mesh || this.count <= MOTION_SPLATS) return;
    const stride = Math.ceil(this.count / MOTION_SPLATS);
    this.motion = discMesh(this.values, this.count, stride, this.motionMaterial);
    this.mesh.visible = false;
    this.group.add(this.motion);
  }

  dropMotion() {
    if (!this.motion) return;
    this.group.remove(this.motion);
    this.motion.geometry.dispose();
    this.motion = null;
  }

  /// One disc per splat: centred, in the plane of its normal, of its radius.
  show(values, count) {
    this.mesh?.geometry.dispose();
    this.dropMotion();
    this.group.clear();
    Object.assign(this, { values, count });
    this.mesh = discMesh(values, count, 1, this.material);
    // No shadows: discs that overlap at slightly different tilts would shade each other's rims.
    this.group.add(this.mesh);
    this.scene3d.requestRender();
  }
}

/// Every @a stride-th of the @a count splats of @a values (centre, normal, radius: 7 floats
/// each) as discs of DISC_SEGMENTS triangles, their area times @a stride, in one geometry: one
/// draw call. (An instanced mesh of the same discs costs a software renderer about 30 µs a
/// disc a frame, SwiftShader drawing instances one by one: 1.7 s a frame for 60,000.)
function discMesh(values, count, stride, material) {
  const discs = Math.ceil(count / stride);
  const positions = new Float32Array(3 * DISC_VERTICES * discs);
  const normals = new Float32Array(3 * DISC_VERTICES * discs);
  const index = new Uint32Array(DISC_INDICES * discs);
  const centre = new THREE.Vector3(), normal = new THREE.Vector3(), u = new THREE.Vector3(), v = new THREE.Vector3();
  const grow = Math.sqrt(stride);
  for (let i = 0, d = 0; i < count; i += stride, ++d) {
    const at = 7 * i;
    centre.set(values[at], values[at + 1], values[at + 2]);
    normal.set(values[at + 3], values[at + 4], values[at + 5]);
    const radius = values[at + 6] * grow;
    // u, v: an orthonormal basis of the disc's plane.
    u.set(Math.abs(normal.x) < 0.9 ? 1 : 0, Math.abs(normal.x) < 0.9 ? 0 : 1, 0).cross(normal).normalize();
    v.crossVectors(normal, u);
    const first = DISC_VERTICES * d;
    for (let k = 0; k < DISC_VERTICES; ++k) {
      const w = 3 * (first + k);
      const [c, s] = k === 0 ? [0, 0] : RIM[k - 1];
      positions[w] = centre.x + radius * (c * u.x + s * v.x);
      positions[w + 1] = centre.y + radius * (c * u.y + s * v.y);
      positions[w + 2] = centre.z + radius * (c * u.z + s * v.z);
      normals[w] = normal.x;
      normals[w + 1] = normal.y;
      normals[w + 2] = normal.z;
    }
    for (let t = 0, w = DISC_INDICES * d; t < DISC_SEGMENTS; ++t, w += 3) {
      index[w] = first;
      index[w + 1] = first + 1 + t;
      index[w + 2] = first + 1 + ((t + 1) % DISC_SEGMENTS);
    }
  }
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  geometry.setAttribute('normal', new THREE.BufferAttribute(normals, 3));
  geometry.setIndex(new THREE.BufferAttribute(index, 1));
  const mesh = new THREE.Mesh(geometry, material);
  mesh.frustumCulled = false;  // the server culled
  return mesh;
}
