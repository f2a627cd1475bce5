// The page of `vdbmesh view`: wires the panel to the 3D view and the server (and, for a label
// map, the list of its labels).
// window.vdbmeshView reports what is on screen, for the browser test.
import * as THREE from 'three';
import { Scene3D } from './scene.js';
import { Model } from './model.js';
import { clipPlanes } from './clip_planes.js';
import { fetchJson, meshQuery } from './mesh_loader.js';
import { HistogramView } from './histogram.js';
import { addHistory, showCounts, showFigures } from './figures.js';
import { Remesher } from './remesher.js';
import { SplatLayer } from './splats.js';
import { LabelList } from './labels.js';
import { MotionNotice } from './motion_notice.js';

const $ = (id) => document.getElementById(id);
const radio = (name) => document.querySelector(`input[name=${name}]:checked`).value;
const state = (window.vdbmeshView = {
  level: '', triangles: 0, meshes: 0, busy: false, timings: [], error: '', figures: null, overBudget: 0, labels: 0, drawnTriangles: 0,
  preparing: false, firstSplatsMs: null, splatMode: false, cameraMovedAt: 0, splats: 0, splatLevel: null, splatCutLevel: null, splatComplete: false, splatViews: 0, splatBusy: false, splatKind: null,
  detail: 'mesh', closeUpTriangles: 0, closeUpBox: null, frameMs: null, frameSamples: 0, moving: false,
});

const scene3d = new Scene3D($('view'));
const motionNotice = new MotionNotice();
scene3d.controls.addEventListener('change', () => {
  state.cameraMovedAt = Date.now();
  motionNotice.cameraChanged();
});
const model = new Model(scene3d);
// Splat mode's close-up: the full mesh's triangles of a box (an open piece: no caps).
const closeUp = new Model(scene3d, { caps: false });
closeUp.group.visible = false;
const splatLayer = new SplatLayer(scene3d, {
  onAsk: () => (state.splatBusy = true),
  onShown: showSplats,
  meshParams: () => meshParams(),
  onCloseUp: showCloseUp,
  onError: (error) => {
    Object.assign(state, { splatBusy: false, error: error.message });
    status(`error: ${error.message}`);
  },
});
scene3d.onMoving = (moving) => {
  state.moving = moving;
  motionNotice.setMoving(moving);
  for (const shown of [model, closeUp, splatLayer]) shown.setMoving(moving);
};
scene3d.onFrameTime = ({ ms, frames, triangles }) => {
  Object.assign(state, { frameMs: ms, frameSamples: frames, frameTriangles: triangles });
  const shown = state.splatMode ? state.detail : `${state.level} mesh`;
  $('frame-time').textContent = `frame time while moving: ${ms.toFixed(1)} ms (median of the last ${frames} frames; ` +
    `${shown}, ${triangles.toLocaleString('en-US')} triangles drawn while moving)`;
};
let info;
let histogram;
let labelList;
let fitted = false;

function status(text) {
  $('status').textContent = text;
}

function meshParams() {
  const method = $('method').value;
  const parameter = Number($('method-parameter').value);
  return {
    method,
    iso: info.scan ? Number($('iso-value').value) : undefined,
    error: method === 'dc' ? parameter : 0,
    adaptivity: method === 'openvdb' ? Math.min(parameter, 1) : 0,
  };
}

function applyClip() {
  if (!model.geometry) return;
  const settings = {
    mode: $('clip-mode').value, axis: Number($('clip-axis').value), flip: $('clip-flip').checked,
    position: Number($('clip-position').value), thickness: Number($('clip-thickness').value),
  };
  const planes = clipPlanes(settings, model.geometry.boundingBox);
  model.setClipPlanes(planes, model.geometry.boundingBox);
  closeUp.setClipPlanes(planes, model.geometry.boundingBox);
  splatLayer.setClipPlanes(planes);
}

/// The close-up's triangles on screen with the splats (null: none).
function showCloseUp(mesh) {
  if (mesh) {
    closeUp.setGeometry(mesh.geometry);
    closeUp.setClipPlanes(closeUp.planes, model.geometry.boundingBox);
  }
  closeUp.group.visible = Boolean(mesh) && state.splatMode;
  scene3d.requestRender();
}

/// The figures of what splat mode shows: the close-up's triangles where the view is close, and
/// the splats (how many, the coarsest level standing for its children, the finest level: cubes
/// of 2^(level+1) voxels).
function showSplats(shown) {
  state.firstSplatsMs ??= performance.now();  // since the page's navigation began
  Object.assign(state, {
    splats: shown.splats, splatKind: shown.kind, splatLevel: shown.level, splatCutLevel: shown.cutLevel, splatComplete: shown.complete, splatViews: state.splatViews + 1, splatBusy: false,
    detail: shown.closeUp ? 'triangles' : 'splats', closeUpTriangles: shown.closeUp?.triangles ?? 0, closeUpBox: shown.closeUp?.box ?? null,
  });
  const cube = (level) => `${2 ** (level + 1)}³ voxels`;
  const detail = shown.cutLevel < 0 ? 'full detail' : `coarsest level ${shown.cutLevel} (${cube(shown.cutLevel)})`;
  const triangles = shown.closeUp
    ? `<span id="detail">triangles</span> close up: ${shown.closeUp.triangles.toLocaleString('en-US')} of the full mesh ` +
      `(voxels ${shown.closeUp.box.replace(/,/g, ' ')}, meshed in ${shown.closeUp.seconds.toFixed(2)} s); splats elsewhere: `
    : '<span id="detail">splats</span>: ';
  // The topology preview: a splat per leaf placed from the active voxels alone (no value read),
  // until the server has fitted the tree.
  const kind = shown.kind === 'preview' ? '<span id="splat-kind">topology preview</span> (a splat per leaf from the active voxels; the fit follows), '
    : '<span id="splat-kind">fitted</span> ';
  $('splat-figures').innerHTML = `${triangles}${kind}${shown.splats.toLocaleString('en-US')} splats, ${detail}, finest level ${shown.level} ` +
    `(${cube(shown.level)})${shown.complete ? '' : ', budget reached'}; tree of ${shown.treeNodes.toLocaleString('en-US')} ` +
    `nodes built in ${shown.seconds.toFixed(2)} s; view in ${shown.ms.toFixed(0)} ms`;
  const what = shown.kind === 'preview' ? 'topology preview' : 'splats';
  status(shown.closeUp ? `triangles close up, splats elsewhere: ${detail}` : `${what}: ${detail}`);
}

function setSplatMode(on) {
  state.splatMode = on;
  scene3d.resetFrameTimes();  // a frame time is of one mode
  state.detail = on ? 'splats' : 'mesh';
  model.group.visible = !on;
  closeUp.group.visible = on && Boolean(state.closeUpBox);
  splatLayer.setEnabled(on, info.scan ? Number($('iso-value').value) : undefined);
}

function showMesh(mesh, level, params) {
  model.setGeometry(mesh.geometry, info.labels);
  labelList?.visible.forEach((visible, index) => model.setLabelVisible(index, visible));
  state.drawnTriangles = labelList ? labelList.drawn() : mesh.triangles;
  applyClip();
  if (!fitted) {
    scene3d.fitTo(mesh.geometry.boundingBox);
    scene3d.setView('home');
    fitted = true;
  }
  Object.assign(state, { level, triangles: mesh.triangles, meshes: state.meshes + 1, overBudget: 0 });
  showCounts($('figures'), mesh, level === 'coarse' ? 'coarse preview' : 'analysing…');
  if (level === 'full' && info.scan) {
    addHistory($('history'), params, mesh);
    $('history-box').classList.remove('hidden');
  }
  $('budget').classList.add('hidden');
}

function showOverBudget(triangles, estimated) {
  Object.assign(state, { overBudget: triangles, overBudgetEstimated: estimated });
  const budget = $('budget');
  const count = `${estimated ? 'about ' : ''}${triangles.toLocaleString('en-US')}`;
  // A model read by region is never meshed whole: splats show it, close-ups show triangles.
  const offer = estimated ? 'turn splats on to see it in detail.' : '<button id="load-full">Show the full mesh</button>';
  budget.innerHTML = `The full mesh has ${count} triangles, over the budget of ` +
    `${info.triangle_budget.toLocaleString('en-US')}: the coarse one is shown; ${offer}`;
  budget.classList.remove('hidden');
  if (!estimated) $('load-full').onclick = () => remesh(false);
}

const remesher = new Remesher(false, 0, {
  onMesh: showMesh,
  onOverBudget: showOverBudget,
  onFigures: (figures) => {
    state.figures = figures;
    showFigures($('figures'), figures, state.level === 'coarse' ? 'of the full mesh; the coarse one is shown' : '');
  },
}, () => scene3d.nextRender());

async function remesh(withinBudget = true) {
  state.busy = true;
  status('meshing…');
  try {
    const timings = await remesher.run(meshParams(), withinBudget);
    if (!timings) return;
    state.timings.push(timings);
    const shown = timings.coarseMs ? `coarse ${timings.coarseMs.toFixed(0)} ms` : '';
    const full = timings.fullMs ? `full ${timings.fullMs.toFixed(0)} ms` : '';
    status([shown, full].filter(Boolean).join(', ') || 'ready');
    state.busy = false;
  } catch (error) {
    Object.assign(state, { busy: false, error: error.message });
    status(`error: ${error.message}`);
  }
}

function setIso(value, andRemesh) {
  const { value_min: min, value_max: max } = info.scan;
  const iso = Math.min(Math.max(value, min), max);
  $('iso').value = iso;
  $('iso-value').value = Number(iso.toPrecision(6));
  histogram.setIso(iso);
  if (andRemesh) {
    remesh();
    splatLayer.setIso(iso);
  }
}

function setUpScan(scan) {
  $('scan-controls').classList.remove('hidden');
  const slider = $('iso');
  Object.assign(slider, { min: scan.value_min, max: scan.value_max, step: (scan.value_max - scan.value_min) / 1000 || 1 });
  $('iso-hint').textContent = `Otsu: ${Number(scan.suggested_iso.toPrecision(5))}`;
  $('iso-hint').title = scan.suggested_reason;
  histogram = new HistogramView($('histogram'), scan, (value) => setIso(value, true));
  setIso(scan.initial_iso, false);
  slider.addEventListener('input', () => setIso(Number(slider.value), false));
  slider.addEventListener('change', () => setIso(Number(slider.value), true));
  $('iso-value').addEventListener('change', () => setIso(Number($('iso-value').value), true));
  for (const id of ['method', 'method-parameter']) {
    $(id).addEventListener('change', () => {
      remesh();
      if (splatLayer.enabled) splatLayer.refresh();  // the close-up's triangles are the method's
    });
  }
}

function download(url, name) {
  const link = Object.assign(document.createElement('a'), { href: url, download: name });
  document.body.append(link);
  link.click();
  link.remove();
}

function setUpPanel() {
  $('reset-view').onclick = () => scene3d.setView('home');
  for (const button of document.querySelectorAll('[data-axis]')) button.onclick = () => scene3d.setView(button.dataset.axis);
  for (const input of document.querySelectorAll('input[name=style]')) {
    input.onchange = () => {
      for (const shown of [model, closeUp]) shown.setStyle(radio('style'));
      applyClip();
    };
  }
  for (const input of document.querySelectorAll('input[name=shading]')) {
    input.onchange = () => { for (const shown of [model, closeUp]) shown.setFlatShading(radio('shading') === 'flat'); };
  }
  $('shadows').onchange = () => scene3d.setShadows($('shadows').checked);
  $('splats').onchange = () => setSplatMode($('splats').checked);
  for (const id of ['clip-mode', 'clip-axis', 'clip-flip', 'clip-position', 'clip-thickness']) $(id).addEventListener('input', applyClip);
  for (const button of document.querySelectorAll('[data-format]')) {
    const format = button.dataset.format;
    button.onclick = () => download(`/api/download?${meshQuery({ ...meshParams(), level: 'full', format })}`, `mesh.${format}`);
  }
  $('save-png').onclick = async () => download(URL.createObjectURL(await scene3d.snapshot()), 'view.png');
}

/// A lattice is shown by its splats alone (`vdbmesh lattice --view`): never meshed, framed by its box.
/// The splats of the first picture of a model whose tree is ready (the full budget's follow).
const FIRST_SPLATS = 15000;

function setUpLattice(lattice) {
  scene3d.fitTo(new THREE.Box3(new THREE.Vector3(...lattice.box_min), new THREE.Vector3(...lattice.box_max)));
  scene3d.setView('home');
  fitted = true;
  $('splat-controls').classList.remove('hidden');
  Object.assign($('splats'), { checked: true, disabled: true });
  splatLayer.quickFirst(FIRST_SPLATS);
  setSplatMode(true);
}

/// A .vdb whose splat tree was made before serving (`view --splats FILE`), or shown first by its
/// topology preview while the server fits it (`view scan.vdb`): the splats at once,
/// framed by their box, while the server prepares the histogram and coarse grid; the iso
/// slider and the coarse mesh come when it is done (splat mode stays on). A splat file alone
/// (`view scan.splat`, kind "splats"): the splats only.
async function startWithSplats(splats) {
  scene3d.fitTo(new THREE.Box3(new THREE.Vector3(...splats.box_min), new THREE.Vector3(...splats.box_max)));
  scene3d.setView('home');
  fitted = true;
  $('splat-controls').classList.remove('hidden');
  Object.assign($('splats'), { checked: true, disabled: true });  // no mesh to switch to yet
  splatLayer.quickFirst(FIRST_SPLATS);
  setSplatMode(true);
  if (info.kind === 'splats') {
    $('figures').textContent = `the splat file alone (${splats.nodes.toLocaleString('en-US')} splats at ${splats.iso}): ` +
      'meshes, the isovalue and close-ups need the grid it was fitted to (vdbmesh view scan.vdb --splats FILE)';
    return;
  }
  state.preparing = Boolean(info.preparing);
  if (!info.preparing) return setUpPreparedScan();
  motionNotice.enabled = true;  // the server's background work pauses while the camera moves
  const preparing = 'histogram and coarse mesh: being prepared by the server (a pass over the grid)…';
  $('figures').textContent = splats.preview ? 'the splat tree: being fitted by the server (a pass over the grid); then the ' + preparing : preparing;
  const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));
  // The server's pass takes every core: it starts once the full budget's splats are drawn.
  while (state.splatViews < 2 && !state.error) await sleep(100);
  info = await fetchJson('/api/info?prepare=1');
  // A topology preview is fitted first (then the pass): the splats of the same view are asked
  // for again once the fitted tree is there.
  let preview = Boolean(splats.preview);
  while ((info.preparing || preview) && !info.prepare_error) {
    await sleep(1000);
    info = await fetchJson('/api/info');
    if (preview && !info.splats.preview) {
      preview = false;
      $('figures').textContent = preparing;
      splatLayer.refresh();
    }
  }
  return setUpPreparedScan();
}

async function setUpPreparedScan() {
  state.preparing = false;
  motionNotice.enabled = false;
  if (info.prepare_error) throw new Error(info.prepare_error);
  $('splats').disabled = false;
  setUpScan(info.scan);
  await remesh();
}

async function start() {
  const asked = fetchJson('/api/info');
  // The discs' shaders compiled while the server answers (it may be reading or fitting for
  // seconds): under a software renderer they took most of the first splats' drawing.
  splatLayer.precompile();
  info = await asked;
  document.title = `${info.name} · vdbmesh view`;
  $('title').textContent = info.name;
  Object.assign(remesher, { isScan: info.kind === 'scan', budget: info.triangle_budget });
  setUpPanel();
  if (info.splats && !info.scan) return startWithSplats(info.splats);
  if (info.scan) setUpScan(info.scan);
  if (info.scan) $('splat-controls').classList.remove('hidden');
  if (info.labels) {
    labelList = new LabelList($('labels-box'), info.labels, (index, visible) => model.setLabelVisible(index, visible),
      (drawn) => (state.drawnTriangles = drawn));
    state.labels = info.labels.length;
  }
  if (info.lattice) setUpLattice(info.lattice);
  else await remesh();
}

start().catch((error) => {
  state.error = error.message;
  status(`error: ${error.message}`);
});
