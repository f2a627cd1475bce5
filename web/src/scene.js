// The 3D view: renderer, camera with orbit controls, lights with shadows, and the views the
// buttons ask for. It draws only when something changed.
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';

const BACKGROUND = 0x0f1115;
const FRAME_SAMPLES = 30;  // the frame time shown is the median of this many frames
const MOVING_PIXEL_RATIO = 0.4;  // of the device's, while the camera moves
const SETTLE_MS = 250;           // the camera counts as still after this long without a change

const AXIS_VIEWS = {
  '+x': { direction: [1, 0, 0], up: [0, 0, 1] },
  '-x': { direction: [-1, 0, 0], up: [0, 0, 1] },
  '+y': { direction: [0, 1, 0], up: [0, 0, 1] },
  '-y': { direction: [0, -1, 0], up: [0, 0, 1] },
  '+z': { direction: [0, 0, 1], up: [0, 1, 0] },
  '-z': { direction: [0, 0, -1], up: [0, 1, 0] },
};
const HOME_VIEW = { direction: [0.6, -1, 0.7], up: [0, 0, 1] };

export class Scene3D {
  constructor(container) {
    this.container = container;
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true, stencil: true });
    this.renderer.setPixelRatio(window.devicePixelRatio);
    this.renderer.setClearColor(BACKGROUND);
    this.renderer.localClippingEnabled = true;
    this.renderer.shadowMap.enabled = true;
    this.renderer.shadowMap.type = THREE.PCFSoftShadowMap;
    // The sun is fixed in the world: its shadow map is drawn again only when the scene changes
    // (requestRender()), not when the camera moves.
    this.renderer.shadowMap.autoUpdate = false;
    container.prepend(this.renderer.domElement);

    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(35, 1, 0.01, 1000);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.addEventListener('change', () => this.cameraMoved());
    this.frameTimes = [];
    this.shadows = true;
    this.addLights();
    this.bounds = new THREE.Box3(new THREE.Vector3(-1, -1, -1), new THREE.Vector3(1, 1, 1));

    new ResizeObserver(() => this.resize()).observe(container);
    this.resize();
    this.renderer.setAnimationLoop(() => this.renderIfNeeded());
  }

  addLights() {
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x404050, 1.2));
    this.sun = new THREE.DirectionalLight(0xffffff, 2.2);
    this.sun.castShadow = true;
    this.sun.shadow.mapSize.set(2048, 2048);
    this.sun.shadow.bias = -0.0005;
    this.sun.shadow.normalBias = 0.02;
    this.scene.add(this.sun, this.sun.target);
    this.ground = new THREE.Mesh(new THREE.PlaneGeometry(1, 1), new THREE.ShadowMaterial({ opacity: 0.35 }));
    this.ground.receiveShadow = true;
    this.scene.add(this.ground);
  }

  /// Places the light, its shadow camera and the ground around @a box (world units).
  fitTo(box) {
    this.bounds.copy(box);
    const centre = box.getCenter(new THREE.Vector3());
    const radius = Math.max(box.getSize(new THREE.Vector3()).length() / 2, 1e-6);
    this.sun.position.copy(centre).add(new THREE.Vector3(0.5, -0.8, 1.6).multiplyScalar(2 * radius));
    this.sun.target.position.copy(centre);
    const shadow = this.sun.shadow.camera;
    Object.assign(shadow, { left: -radius * 1.5, right: radius * 1.5, top: radius * 1.5, bottom: -radius * 1.5 });
    shadow.near = 0.1 * radius;
    shadow.far = 5 * radius;
    shadow.updateProjectionMatrix();
    this.ground.scale.setScalar(6 * radius);
    this.ground.position.set(centre.x, centre.y, box.min.z - 0.01 * radius);
    this.camera.near = radius / 100;
    this.camera.far = radius * 100;
    this.requestRender();
  }

  setShadows(on) {
    this.shadows = on;
    this.showShadows();
  }

  /// Shadows when asked for, and not while the camera moves (their soft edges' samples cost
  /// more than the rest of a software-rendered frame).
  showShadows() {
    const on = this.shadows && !this.moving;
    this.sun.castShadow = on;
    this.ground.visible = on;
    this.requestRender();
  }

  /// Looks at the bounds from @a name ('+x' ... '-z', or 'home').
  setView(name) {
    const view = AXIS_VIEWS[name] ?? HOME_VIEW;
    const centre = this.bounds.getCenter(new THREE.Vector3());
    const radius = this.bounds.getSize(new THREE.Vector3()).length() / 2;
    const distance = radius / Math.sin(THREE.MathUtils.degToRad(this.camera.fov / 2));
    const direction = new THREE.Vector3(...view.direction).normalize();
    this.camera.up.set(...view.up);
    this.camera.position.copy(centre).addScaledVector(direction, distance);
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(centre);
    this.controls.update();
    this.requestRender();
  }

  resize() {
    const { clientWidth: width, clientHeight: height } = this.container;
    if (width === 0 || height === 0) return;
    this.renderer.setSize(width, height, false);
    this.camera.aspect = width / height;
    this.camera.updateProjectionMatrix();
    this.requestRender();
  }

  /// Draws again after a change to the scene (its shadows too).
  requestRender() {
    this.dirty = true;
    this.renderer.shadowMap.needsUpdate = true;
  }

  /// While the camera moves, frames are drawn at a fraction of the resolution, without
  /// multisampling and without shadows (the user sees motion, not detail); once it has been
  /// still for SETTLE_MS, in full.
  cameraMoved() {
    this.cameraChanged = true;
    this.dirty = true;
    if (!this.moving) this.setMoving(true);
    clearTimeout(this.settle);
    this.settle = setTimeout(() => this.setMoving(false), SETTLE_MS);
  }

  setMoving(moving) {
    this.moving = moving;
    this.onMoving?.(moving);
    this.renderer.setPixelRatio(window.devicePixelRatio * (moving ? MOVING_PIXEL_RATIO : 1));
    this.resize();
    this.showShadows();
  }

  /// A frame while the camera moves: the scene drawn at MOVING_PIXEL_RATIO into a target
  /// without multisampling, then stretched over the canvas. SwiftShader's multisampling
  /// (antialias) cost about 40 ms a frame of splats on the busy 2-core machine (issue 30:
  /// 93 ms with it, 54 ms without, at half resolution); stills keep it.
  renderMoving() {
    const canvas = this.renderer.domElement;
    const width = canvas.width, height = canvas.height;
    if (!this.motionTarget) {
      this.motionTarget = new THREE.WebGLRenderTarget(width, height, { samples: 0, stencilBuffer: true });
      this.motionQuad = new THREE.Mesh(new THREE.PlaneGeometry(2, 2),
        new THREE.MeshBasicMaterial({ map: this.motionTarget.texture, depthTest: false, depthWrite: false }));
      this.motionScene = new THREE.Scene().add(this.motionQuad);
      this.motionCamera = new THREE.OrthographicCamera(-1, 1, 1, -1, 0, 1);
    }
    this.motionTarget.setSize(width, height);
    this.renderer.setRenderTarget(this.motionTarget);
    this.renderer.render(this.scene, this.camera);
    this.renderer.setRenderTarget(null);
    const triangles = this.renderer.info.render.triangles;
    this.renderer.render(this.motionScene, this.motionCamera);
    return triangles;
  }

  /// Called on every animation frame. A frame drawn because the camera moved is timed from its
  /// start to the next animation frame, which the browser gives once that frame is drawn and
  /// composited: the frame time a user sees while rotating (rendering alone, even to
  /// gl.finish(), leaves out most of a software renderer's work).
  renderIfNeeded() {
    const now = performance.now();
    if (this.timedFrameStart !== undefined) this.recordFrameTime(now - this.timedFrameStart);
    this.timedFrameStart = undefined;
    if (!this.dirty) return;
    this.dirty = false;
    if (this.cameraChanged) this.timedFrameStart = now;
    this.cameraChanged = false;
    let triangles;
    if (this.moving) triangles = this.renderMoving();
    else {
      this.renderer.render(this.scene, this.camera);
      triangles = this.renderer.info.render.triangles;
    }
    if (this.timedFrameStart !== undefined) this.movingTriangles = triangles;
    const waiting = this.waitingForRender ?? [];
    this.waitingForRender = [];
    if (waiting.length > 0) this.renderer.getContext().finish();
    for (const resolve of waiting) resolve();
  }

  /// Forgets the frame times measured so far (what is drawn changed).
  resetFrameTimes() {
    this.frameTimes = [];
  }

  recordFrameTime(ms) {
    this.frameTimes.push(ms);
    if (this.frameTimes.length > FRAME_SAMPLES) this.frameTimes.shift();
    if (this.frameTimes.length % 10 === 0 || this.frameTimes.length === FRAME_SAMPLES) this.onFrameTime?.(this.frameTime());
  }

  /// The median frame time (ms) of the last frames drawn while the camera moved, how many, and
  /// the triangles the last of them drew.
  frameTime() {
    const sorted = [...this.frameTimes].sort((a, b) => a - b);
    return { ms: sorted.length ? sorted[Math.floor(sorted.length / 2)] : NaN, frames: sorted.length, triangles: this.movingTriangles };
  }

  /// Resolves once the next frame is drawn (its GL commands finished).
  nextRender() {
    this.requestRender();
    return new Promise((resolve) => (this.waitingForRender ??= []).push(resolve));
  }

  /// A PNG of the view, drawn afresh.
  async snapshot() {
    this.renderer.render(this.scene, this.camera);
    return new Promise((resolve) => this.renderer.domElement.toBlob(resolve, 'image/png'));
  }
}
