// The page of `vdbmesh view` in a real browser: Debian's headless Chromium (WebGL through
// SwiftShader) driven by playwright-core from web/node_modules. Starts `vdbmesh view` on a
// torus phantom (or --scan FILE), waits for the model, and checks screenshots by their
// pixels: the model is drawn and centred, the isovalue slider re-meshes (the triangle count
// the page reports and the picture change), wireframe differs from solid, a clip plane
// removes the expected half and caps the cut, splats cover the view and refine on a zoom
// (the page's reported level), and Ctrl-C stops the server cleanly. Then (without --scan)
// `vdbmesh view --labels` on a small label map: the labels listed, coloured, switchable.
// `vdbmesh view scan.vdb` without a splat file: the topology preview first, then the fitted splats.
// Prints the time from releasing the slider to the coarse and the full mesh on screen.
// Exit 0 passed, 1 failed, 77 skipped (no Chromium; a failure under VDBMESH_REQUIRE_BROWSER=1).
//
// node browser_test.mjs --vdbmesh BIN --web WEB_DIR --out SCREENSHOT_DIR
//                       [--scan FILE --iso-to V] [--labels-map FILE] [-- more `vdbmesh view` arguments]
import { execFileSync, spawn } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { createRequire } from 'node:module';
import { changedShare, foreground, pngDecoder, shareWhere } from './pixels.mjs';

const SKIPPED = 77;
const BACKGROUND = [0x0f, 0x11, 0x15];
const CHROMIUM_FLAGS = [
  '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking',
  '--disable-component-update', '--disable-sync', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
];
const isCap = (r, g, b) => r > g + 35 && r > b + 60;  // the cut face's orange, lit or in shade

function parseArguments(argv) {
  const split = argv.indexOf('--');
  const own = split < 0 ? argv : argv.slice(0, split);
  const options = { viewArguments: split < 0 ? [] : argv.slice(split + 1) };
  for (let i = 0; i < own.length; i += 2) options[own[i].replace(/^--/, '').replace(/-(.)/g, (_, c) => c.toUpperCase())] = own[i + 1];
  for (const required of ['vdbmesh', 'web', 'out']) {
    if (!options[required]) throw new Error(`--${required} is required`);
    options[required] = path.resolve(options[required]);
  }
  return options;
}

function skipOrFail(message) {
  if (process.env.VDBMESH_REQUIRE_BROWSER === '1') {
    console.error(`FAIL: ${message} (VDBMESH_REQUIRE_BROWSER=1)`);
    process.exit(1);
  }
  console.log(`SKIP: ${message}`);
  process.exit(SKIPPED);
}

function findChromium() {
  const candidates = [process.env.CHROMIUM, '/usr/bin/chromium', '/usr/bin/chromium-browser'].filter(Boolean);
  return candidates.find((candidate) => fs.existsSync(candidate));
}

/// Starts `vdbmesh view` (or another command serving the page, `lattice ... --view`) and
/// resolves with it and the address it prints.
function startViewer(vdbmesh, viewArguments, command = ['view']) {
  const child = spawn(vdbmesh, [...command, ...viewArguments, '--no-open', '--port', '0'], { stdio: ['ignore', 'pipe', 'inherit'] });
  return new Promise((resolve, reject) => {
    let printed = '';
    child.stdout.on('data', (chunk) => {
      printed += chunk;
      const address = printed.match(/at (http:\/\/\S+)/);
      if (address) resolve({ child, address: address[1] });
    });
    child.on('exit', (code) => reject(new Error(`vdbmesh view exited with ${code} before serving`)));
  });
}

/// Sends Ctrl-C's signal and resolves with the exit code (null when it did not stop in time).
function stopViewer(child) {
  return new Promise((resolve) => {
    const timer = setTimeout(() => resolve(null), 10000);
    child.on('exit', (code) => {
      clearTimeout(timer);
      resolve(code);
    });
    child.kill('SIGINT');
  });
}

class Checks {
  failures = 0;
  expect(condition, message) {
    console.log(`${condition ? 'ok  ' : 'FAIL'} ${message}`);
    if (!condition) this.failures += 1;
  }
}

/// The seconds each part of the run took, printed at the end: where the test's time goes.
class Stages {
  started = Date.now();
  seconds = [];
  async time(name, work) {
    const start = Date.now();
    try {
      return await work();
    } finally {
      this.seconds.push(`${name} ${((Date.now() - start) / 1000).toFixed(1)}`);
    }
  }
  print() {
    console.log(`seconds by part: ${this.seconds.join(', ')}; ${((Date.now() - this.started) / 1000).toFixed(1)} in all`);
  }
}

class PageDriver {
  constructor(page, outDir, decode) {
    Object.assign(this, { page, outDir, decode });
  }

  state() {
    return this.page.evaluate(() => ({ ...window.vdbmeshView }));
  }

  /// Waits until the page is done with meshes newer than @a meshesBefore: a full mesh on
  /// screen, or the coarse one with the full one over the triangle budget.
  async waitForMeshes(meshesBefore, timeout) {
    await this.page.waitForFunction(
      (before) => {
        const s = window.vdbmeshView;
        return s.error || (s.meshes > before && !s.busy && (s.level === 'full' || s.overBudget > 0));
      },
      meshesBefore, { timeout, polling: 100 });
    const state = await this.state();
    if (state.error) throw new Error(`the page reports: ${state.error}`);
    return state;
  }

  /// waitForMeshes(), then the full mesh loaded by the button when it was over the budget (a
  /// grid read by region has no such button: its coarse mesh stays).
  async waitForFullMesh(meshesBefore, timeout) {
    const state = await this.waitForMeshes(meshesBefore, timeout);
    if (state.level === 'full') return state;
    if (state.overBudgetEstimated) {
      console.log(`the full mesh (about ${state.overBudget} triangles) of a grid read by region is not made: the coarse one stays`);
      return state;
    }
    console.log(`the full mesh (${state.overBudget} triangles) is over the budget: loading it with the button`);
    await this.click('#load-full');
    return this.waitForMeshes(state.meshes, timeout);
  }

  frames() {
    return this.page.evaluate(() => new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve))));
  }

  async shot(name) {
    // While the camera moves the page draws at a lower resolution: wait for the full one.
    await this.page.waitForFunction(() => !window.vdbmeshView.moving, null, { polling: 50 });
    await this.frames();
    const png = await this.page.locator('#view canvas').screenshot();
    fs.writeFileSync(path.join(this.outDir, `${name}.png`), png);
    return this.decode(png);
  }

  async click(selector) {
    await this.page.locator(selector).click();
  }
}

async function checkModelDrawn(driver, checks) {
  const solid = await driver.shot('solid');
  const drawn = foreground(solid, BACKGROUND);
  checks.expect(drawn.share > 0.03, `the model covers ${(100 * drawn.share).toFixed(1)}% of the view (> 3%)`);
  const centreX = (drawn.box.minX + drawn.box.maxX) / 2 / solid.width;
  const centreY = (drawn.box.minY + drawn.box.maxY) / 2 / solid.height;
  checks.expect(Math.abs(centreX - 0.5) < 0.2 && Math.abs(centreY - 0.5) < 0.2,
    `the model is centred (box centre at ${centreX.toFixed(2)}, ${centreY.toFixed(2)} of the view)`);
  return solid;
}

async function checkIsoSlider(driver, checks, before, isoTo, timeout) {
  const { triangles } = await driver.state();
  const slider = await driver.page.evaluate(() => {
    const { min, step } = document.getElementById('iso');
    return { min: Number(min), step: Number(step), current: Number(document.getElementById('iso-value').value) };
  });
  const wanted = isoTo ?? slider.current - (slider.current - slider.min) / 2;
  // A range input takes only values on its steps.
  const target = slider.min + Math.round((wanted - slider.min) / slider.step) * slider.step;
  const meshes = (await driver.state()).meshes;
  // Set as a released slider would (input, then change). Playwright's fill() refuses a value the
  // browser rounds onto the step ("Malformed value"), which a scan's fractional step makes.
  await driver.page.locator('#iso').evaluate((input, value) => {
    input.value = value;
    input.dispatchEvent(new Event('input', { bubbles: true }));
    input.dispatchEvent(new Event('change', { bubbles: true }));
  }, String(Number(target.toPrecision(12))));
  const after = await driver.waitForFullMesh(meshes, timeout);
  const shown = await driver.page.locator('#triangle-count').textContent();
  checks.expect(after.triangles !== triangles, `moving the isovalue to ${target} re-meshes: ${triangles} -> ${after.triangles} triangles`);
  checks.expect(Number(shown.replace(/,/g, '')) === after.triangles, `the page shows the new count (${shown})`);
  const image = await driver.shot('solid-after-iso');
  const changed = changedShare(before, image);
  checks.expect(changed > 0.002, `the picture changes with the isovalue (${(100 * changed).toFixed(2)}% of pixels)`);
  const timing = after.timings.filter((run) => run.coarseMs !== undefined).at(-1);  // the slider's, not the button's
  const ms = (value) => (value === undefined ? '-' : `${value.toFixed(0)} ms`);
  console.log(`timing: slider released -> coarse mesh received ${ms(timing.coarseFetchedMs)}, on screen ${ms(timing.coarseMs)}; ` +
    `full mesh received ${ms(timing.fullFetchedMs)}, on screen ${ms(timing.fullMs)}` +
    (timing.fullMs === undefined
      ? ` (over the budget: made, its count received ${ms(timing.overBudgetMs)}; then on screen ${ms(after.timings.at(-1).fullMs)} after the button)`
      : ''));
  return image;
}

async function checkWireframe(driver, checks, solid) {
  await driver.click('input[name=style][value=wireframe]');
  const wire = await driver.shot('wireframe');
  const changed = changedShare(solid, wire);
  checks.expect(changed > 0.02, `wireframe differs from solid (${(100 * changed).toFixed(1)}% of pixels)`);
  checks.expect(foreground(wire, BACKGROUND).share > 0.005, 'the wireframe is drawn');
  await driver.click('input[name=style][value=both]');
  await driver.shot('both');
  await driver.click('input[name=style][value=solid]');
}

async function checkClip(driver, checks) {
  await driver.click('[data-axis="-y"]');
  const front = foreground(await driver.shot('front'), BACKGROUND);
  await driver.page.selectOption('#clip-mode', 'clip');
  const clipped = foreground(await driver.shot('front-clipped-x'), BACKGROUND);
  checks.expect(clipped.right < 0.1 * front.right,
    `clipping at the middle of x removes the right half (${front.right} -> ${clipped.right} pixels)`);
  checks.expect(clipped.left > 0.8 * front.left, `and keeps the left half (${front.left} -> ${clipped.left} pixels)`);
  await driver.click('[data-axis="+x"]');
  const capShare = shareWhere(await driver.shot('side-clipped-x'), isCap);
  checks.expect(capShare > 0.01, `the cut face is capped (${(100 * capShare).toFixed(1)}% of the view)`);
  await driver.page.selectOption('#clip-mode', 'slab');
  await driver.shot('side-slab-x');
  await driver.click('#reset-view');
  await driver.page.selectOption('#clip-mode', 'none');
}

/// Rotates the view by dragging across it and returns the frame time the page measured and
/// shows (the median of the frames drawn while the camera moved); @a what names what is shown.
async function measureRotation(driver, checks, what) {
  const box = await driver.page.locator('#view canvas').boundingBox();
  const y = box.y + box.height / 2;
  await driver.page.mouse.move(box.x + box.width * 0.3, y);
  await driver.page.mouse.down();
  await driver.page.mouse.move(box.x + box.width * 0.7, y, { steps: 15 });
  await driver.page.mouse.move(box.x + box.width * 0.3, y, { steps: 15 });
  await driver.page.mouse.up();
  await driver.frames();
  const state = await driver.state();
  const shown = await driver.page.locator('#frame-time').textContent();
  checks.expect(state.frameSamples >= 10 && state.frameMs > 0 && shown.includes(state.frameMs.toFixed(1)),
    `the page measures the frame time while rotating (${what}) and shows it: ${shown}`);
  console.log(`frame time while rotating (${what}): ${state.frameMs?.toFixed(1)} ms, median of ${state.frameSamples} frames`);
  return state.frameMs;
}

/// Splat mode: the splats cover the view like the mesh, a zoom out coarsens them, a zoom in
/// refines them (the page's reported level, the picture changes) down to the full mesh's
/// triangles close up (the figures say triangles, wireframe shows their edges), and turning it
/// off brings the mesh back.
async function checkSplats(driver, checks, solid, timeout) {
  // The page asks once the camera has been still for 250 ms: wait for the camera to rest a
  // second (wheel events may reach a busy page late) and the last view asked to be drawn.
  const waitForSplats = async (viewsBefore) => {
    await driver.page.waitForFunction(
      (before) => {
        const s = window.vdbmeshView;
        return s.error || (Date.now() - s.cameraMovedAt > 1000 && s.splatViews > before && !s.splatBusy);
      },
      viewsBefore, { timeout, polling: 100 });
    const state = await driver.state();
    if (state.error) throw new Error(`the page reports: ${state.error}`);
    return state;
  };
  const detailShown = async () => driver.page.locator('#detail').textContent();
  const box = await driver.page.locator('#view canvas').boundingBox();
  const wheel = async (steps) => {
    await driver.page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
    for (let i = 0; i < Math.abs(steps); ++i) await driver.page.mouse.wheel(0, Math.sign(steps) * 400);
  };
  const started = Date.now();
  await driver.click('#splats');
  const first = await waitForSplats(0);
  console.log(`splat mode on screen ${Date.now() - started} ms after the switch: ${first.detail}, ${first.splats} splats, ` +
    `${first.closeUpTriangles} triangles close up`);
  // Farther (the model about a quarter of its size): splats alone, as a small model's
  // triangles are cheaper than its splats at the home view.
  await wheel(6);
  const middle = await waitForSplats(first.splatViews);
  const splatted = await driver.shot('splats');
  const drawn = foreground(splatted, BACKGROUND);
  checks.expect(drawn.share > 0.01, `the splats cover ${(100 * drawn.share).toFixed(1)}% of the view (> 1%)`);
  checks.expect(middle.detail === 'splats' && middle.splats > 0 && Number.isInteger(middle.splatLevel),
    `the page reports ${middle.splats} splats at level ${middle.splatLevel} (${middle.detail})`);
  const shown = await driver.page.locator('#splat-figures').textContent();
  checks.expect(shown.includes(`finest level ${middle.splatLevel}`) && (await detailShown()) === 'splats', `the figures name the level shown (${shown})`);
  await measureRotation(driver, checks, `${middle.splats} splats`);
  const rotated = await waitForSplats(middle.splatViews);
  // From afar (the model some ten pixels wide) coarser nodes suffice; then close up.
  await wheel(9);  // 15 steps out in all: farther, the camera's far plane would cut the model
  const coarse = await waitForSplats(rotated.splatViews);
  const far = await driver.shot('splats-far');
  await wheel(-25);
  const zoomed = await waitForSplats(coarse.splatViews);
  const closer = await driver.shot('splats-zoomed');
  const changed = changedShare(far, closer);
  checks.expect(changed > 0.05, `zooming in changes the picture (${(100 * changed).toFixed(1)}% of pixels)`);
  // The page's level: the coarsest node shown in place of its children (-1: full detail).
  checks.expect(coarse.splatCutLevel > 0, `from afar nodes stand for their children (coarsest level ${coarse.splatCutLevel}, ${coarse.splats} splats)`);
  // On a huge model the budget keeps far nodes coarse: then the finest level shown falls.
  checks.expect(zoomed.splatCutLevel < coarse.splatCutLevel || zoomed.splatLevel < coarse.splatLevel,
    `zooming in refines the splats: coarsest level ${coarse.splatCutLevel} -> ${zoomed.splatCutLevel}, finest ${coarse.splatLevel} -> ${zoomed.splatLevel}`);
  // Close up, the full mesh's triangles replace the splats (GET /api/mesh?level=region).
  checks.expect(zoomed.detail === 'triangles' && zoomed.closeUpTriangles > 0 && (await detailShown()) === 'triangles',
    `close up the figures say triangles (${zoomed.closeUpTriangles} triangles of the box ${zoomed.closeUpBox}, ${zoomed.splats} splats elsewhere)`);
  checks.expect(changedShare(splatted, closer) > 0.05, `and the picture differs from the splats' (${(100 * changedShare(splatted, closer)).toFixed(1)}% of pixels)`);
  await driver.click('input[name=style][value=wireframe]');
  const wire = await driver.shot('close-up-wireframe');
  checks.expect(changedShare(closer, wire) > 0.02, `wireframe shows the close-up's edges (${(100 * changedShare(closer, wire)).toFixed(1)}% of pixels change)`);
  await driver.click('input[name=style][value=solid]');
  await driver.click('#splats');
  await driver.click('#reset-view');
  const mesh = await driver.shot('splats-off');
  checks.expect(changedShare(solid, mesh) < 0.02, 'turning splats off shows the mesh again');
}

/// A small label map (NIfTI-1, u8, 32^3): two touching spheres (labels 1 and 2, sharing a wall)
/// and a bar (label 3), with a FreeSurfer-style table beside it naming and colouring 1 and 2
/// (3 gets the palette's colour and "label 3").
function writeLabelMap(folder) {
  const n = 32;
  const header = Buffer.alloc(352);
  header.writeInt32LE(348, 0);
  [3, n, n, n, 1, 1, 1, 1].forEach((d, i) => header.writeInt16LE(d, 40 + 2 * i));
  header.writeInt16LE(2, 70);  // DT_UINT8
  header.writeInt16LE(8, 72);
  [1, 1, 1, 1].forEach((d, i) => header.writeFloatLE(d, 76 + 4 * i));
  header.writeFloatLE(352, 108);
  header.writeUInt8(2, 123);  // millimetres
  header.write('n+1\0', 344, 'latin1');
  const voxels = Buffer.alloc(n * n * n);
  for (let z = 0; z < n; ++z)
    for (let y = 0; y < n; ++y)
      for (let x = 0; x < n; ++x) {
        const inSphere = (cx) => (x - cx) ** 2 + (y - 16) ** 2 + (z - 16) ** 2 <= 49;
        voxels[(z * n + y) * n + x] = inSphere(21) ? 2 : inSphere(11) ? 1 : y >= 4 && y < 8 && z >= 8 && z < 24 && x >= 6 && x < 26 ? 3 : 0;
      }
  const map = path.join(folder, 'labels.nii');
  fs.writeFileSync(map, Buffer.concat([header, voxels]));
  fs.writeFileSync(path.join(folder, 'labels_LUT.txt'), '0 Unknown 0 0 0 0\n1 Left 230 30 30 0\n2 Right 30 200 30 0\n');
  return map;
}

const isRed = (r, g, b) => r > g + 60 && r > b + 60;
const isGreen = (r, g, b) => g > r + 50 && g > b + 50;

/// `vdbmesh view MAP --labels all`: the list names the labels, they are drawn in the table's
/// colours, and switching one off takes its triangles out of the count drawn and its colour
/// out of the picture; all brings it back. With --labels-map FILE (e.g. an atlas, for its
/// screenshots) the checks that know writeLabelMap()'s names and colours are left out.
async function checkLabels(browser, options, scratch, decode, checks, timeout) {
  const ours = !options.labelsMap;
  const viewer = await startViewer(options.vdbmesh, [options.labelsMap ?? writeLabelMap(scratch), '--labels', 'all']);
  try {
    const page = await browser.newPage({ viewport: { width: 1000, height: 700 } });
    page.on('pageerror', (error) => checks.expect(false, `no error in the labels page: ${error.message}`));
    page.setDefaultTimeout(timeout);
    const driver = new PageDriver(page, options.out, decode);
    await page.goto(viewer.address);
    const before = await driver.waitForFullMesh(0, timeout);
    const names = await page.locator('#labels label').allTextContents();
    const listed = ours ? 3 : before.labels;
    checks.expect(before.labels === listed && names.length === listed && listed > 0,
      `the page lists the map's ${listed} labels (${names.slice(0, 3).join(', ')}${listed > 3 ? ', …' : ''})`);
    if (ours) checks.expect(names[0].includes('Left') && names[1].includes('Right') && names[2].includes('label 3'), 'named by the table (else "label N")');
    checks.expect(before.drawnTriangles === before.triangles, `all drawn at first (${before.drawnTriangles} of ${before.triangles} triangles)`);
    await page.screenshot({ path: path.join(options.out, 'labels-page.png') });
    const all = await driver.shot('labels');
    const red = shareWhere(all, isRed), green = shareWhere(all, isGreen);
    if (ours) checks.expect(red > 0.01 && green > 0.01, `labels 1 and 2 in the table's red and green (${(100 * red).toFixed(1)}%, ${(100 * green).toFixed(1)}% of the view)`);
    await page.locator('#labels input').first().uncheck();
    const without = await driver.state();
    const shown = Number((await page.locator('#drawn-triangles').textContent()).replace(/,/g, ''));
    checks.expect(without.drawnTriangles < before.drawnTriangles && shown === without.drawnTriangles,
      `switching the first label off draws fewer triangles: ${before.drawnTriangles} -> ${without.drawnTriangles} (the page shows ${shown})`);
    const off = await driver.shot('labels-1-off');
    if (ours) {
      checks.expect(shareWhere(off, isRed) < 0.1 * red && changedShare(all, off) > 0.01,
        `and takes its red out of the picture (${(100 * shareWhere(off, isRed)).toFixed(2)}% red left, ${(100 * changedShare(all, off)).toFixed(1)}% of pixels changed)`);
    }
    await driver.click('#labels-none');
    const none = await driver.state();
    const empty = foreground(await driver.shot('labels-none'), BACKGROUND).share;
    checks.expect(none.drawnTriangles === 0 && empty < 0.002, `"none" draws nothing (${none.drawnTriangles} triangles, ${(100 * empty).toFixed(2)}% of the view)`);
    await driver.click('#labels-all');
    const again = await driver.state();
    checks.expect(again.drawnTriangles === before.drawnTriangles && changedShare(all, await driver.shot('labels-all-again')) < 0.005,
      'the "all" button brings it back');
    await page.close();
  } finally {
    checks.expect((await stopViewer(viewer.child)) === 0, 'the labels viewer stops cleanly on SIGINT (exit 0)');
  }
}

/// `vdbmesh lattice gyroid ... --view`: the page shows the lattice by splats at once (no mesh),
/// covering the view, and zooming in refines them. --lattice-box 4096 for the gyroid.
/// By default 256^3 (four periods a side): its splats are still over the page's budget, so the
/// first view is coarse and a zoom refines it, and its fit is an eighth of 512^3's (which took
/// 30 s of the run under a loaded machine's nice 15).
async function checkLattice(browser, options, decode, checks, timeout) {
  const side = options.latticeBox ?? '256';
  const started = Date.now();
  const viewer = await startViewer(options.vdbmesh, ['gyroid', '--period', '64', '--thickness', '4', '--box', side, '--voxel', '1'],
    ['lattice', '--view']);
  try {
    const page = await browser.newPage({ viewport: { width: 900, height: 700 } });
    page.on('pageerror', (error) => checks.expect(false, `no error in the lattice page: ${error.message}`));
    page.setDefaultTimeout(timeout);
    const driver = new PageDriver(page, options.out, decode);
    await page.goto(viewer.address);
    const waitForSplats = async (before) => {
      await page.waitForFunction((views) => {
        const s = window.vdbmeshView;
        return s.error || (Date.now() - s.cameraMovedAt > 1000 && s.splatViews > views && !s.splatBusy);
      }, before, { timeout, polling: 100 });
      const state = await driver.state();
      if (state.error) throw new Error(`the lattice page reports: ${state.error}`);
      return state;
    };
    // The quick first 15,000 splats, then the budget's: the second view is the one checked.
    const first = await waitForSplats(1);
    const whole = await driver.shot('lattice');
    console.log(`the ${side}^3 gyroid on the page ${Date.now() - started} ms after starting vdbmesh lattice --view: ` +
      `${first.splats} splats, finest level ${first.splatLevel}, coarsest ${first.splatCutLevel}`);
    const drawn = foreground(whole, BACKGROUND).share;
    checks.expect(drawn > 0.2, `the lattice covers ${(100 * drawn).toFixed(1)}% of the view (> 20%)`);
    const shown = await page.locator('#splat-figures').textContent();
    checks.expect(first.splats > 0 && shown.includes(`finest level ${first.splatLevel}`), `its figures name the level shown (${shown})`);
    const box = await page.locator('#view canvas').boundingBox();
    await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
    for (let i = 0; i < 12; ++i) await page.mouse.wheel(0, -400);
    const zoomed = await waitForSplats(first.splatViews);
    const closer = await driver.shot('lattice-zoomed');
    checks.expect(changedShare(whole, closer) > 0.05, `zooming into the lattice changes the picture (${(100 * changedShare(whole, closer)).toFixed(1)}% of pixels)`);
    checks.expect(zoomed.splatLevel < first.splatLevel || zoomed.splatCutLevel < first.splatCutLevel,
      `and refines its splats: finest level ${first.splatLevel} -> ${zoomed.splatLevel}, coarsest ${first.splatCutLevel} -> ${zoomed.splatCutLevel}`);
    await page.close();
  } finally {
    checks.expect((await stopViewer(viewer.child)) === 0, 'the lattice viewer stops cleanly on SIGINT (exit 0)');
  }
}

/// `view scan.vdb --splats FILE`: the first run fits and writes the file; the second opens in
/// splat mode at once, then gets the iso slider and the coarse mesh from the background pass.
/// Then `view FILE` alone: the splats, no mesh, the page saying why.
async function checkSplatFile(browser, options, scratch, scan, decode, checks, timeout) {
  const vdb = path.join(scratch, 'splat-file.vdb');
  const splats = path.join(scratch, 'splat-file.splat');
  execFileSync(options.vdbmesh, ['convert', scan, '--iso', '0.5', '-o', vdb, '--quiet']);
  for (const run of ['fits', 'reads']) {
    const viewer = await startViewer(options.vdbmesh, [vdb, '--splats', splats]);
    try {
      checks.expect(fs.existsSync(splats), `view --splats ${run} the splat file (${fs.existsSync(splats) ? fs.statSync(splats).size : 0} bytes)`);
      if (run === 'fits') continue;
      const page = await browser.newPage({ viewport: { width: 900, height: 700 } });
      page.on('pageerror', (error) => checks.expect(false, `no error in the splat file's page: ${error.message}`));
      page.setDefaultTimeout(timeout);
      const driver = new PageDriver(page, options.out, decode);
      await page.goto(viewer.address);
      // The page's state when its first splats are drawn, read in the same task that draws them
      // (as the topology preview's): under load the background pass's coarse mesh can arrive
      // before a later read (a fresh clone's run: "meshes 2").
      const first = await (await page.waitForFunction(() => (window.vdbmeshView.splatViews > 0 || window.vdbmeshView.error) &&
        { ...window.vdbmeshView }, null, { polling: 50 })).jsonValue();
      checks.expect(!first.error && first.splatMode && first.meshes === 0,
        `the first picture is the splat file's splats (${first.splats} splats, meshes ${first.meshes}) ${first.error ?? ''}`);
      const drawn = foreground(await driver.shot('splat-file'), BACKGROUND).share;
      checks.expect(drawn > 0.05, `the splats cover ${(100 * drawn).toFixed(1)}% of the view (> 5%)`);
      await page.waitForFunction(() => window.vdbmeshView.meshes > 0 || window.vdbmeshView.error, null, { polling: 100 });
      const later = await driver.state();
      const slider = await page.locator('#scan-controls').isVisible();
      checks.expect(!later.error && !later.preparing && later.splatMode && slider && !(await page.locator('#splats').isDisabled()),
        `then the background pass brings the iso slider and the coarse mesh (${later.level}, ${later.triangles} triangles), splats kept on`);
      await page.close();
    } finally {
      checks.expect((await stopViewer(viewer.child)) === 0, `view --splats (${run}) stops cleanly on SIGINT (exit 0)`);
    }
  }
  await checkSplatsAlone(browser, options, splats, decode, checks, timeout);
}

/// `view scan.vdb` without a splat file: the topology preview at once (a splat per leaf, no
/// value read), the page saying so; then the fitted splats in its place, then the coarse mesh.
async function checkTopologyPreview(browser, options, scratch, decode, checks, timeout) {
  const vdb = path.join(scratch, 'splat-file.vdb');  // checkSplatFile's
  const viewer = await startViewer(options.vdbmesh, [vdb]);
  try {
    const page = await browser.newPage({ viewport: { width: 900, height: 700 } });
    page.on('pageerror', (error) => checks.expect(false, `no error in the topology preview's page: ${error.message}`));
    page.setDefaultTimeout(timeout);
    const driver = new PageDriver(page, options.out, decode);
    await page.goto(viewer.address);
    // What the page shows when its first splats are drawn, read in the same task that draws them:
    // on a small file the fit that follows the first picture can replace the preview before a
    // later read (a screenshot under load takes longer than the fit).
    const first = await (await page.waitForFunction(() => (window.vdbmeshView.splatViews > 0 || window.vdbmeshView.error) && {
      error: window.vdbmeshView.error, kind: window.vdbmeshView.splatKind, splats: window.vdbmeshView.splats, meshes: window.vdbmeshView.meshes,
      said: document.querySelector('#splat-kind')?.textContent ?? '',
    }, null, { polling: 50 })).jsonValue();
    const preview = await driver.shot('topology-preview');
    const previewShare = foreground(preview, BACKGROUND).share;
    const shotOfThePreview = (await driver.state()).splatKind === 'preview';  // no switch until after the shot
    checks.expect(!first.error && first.kind === 'preview' && first.meshes === 0 && previewShare > 0.05,
      `view FILE.vdb first shows the topology preview (${first.kind}, ${first.splats} splats, ${(100 * previewShare).toFixed(1)}% of the view) ${first.error}`);
    checks.expect(first.said === 'topology preview', `and its figures say "topology preview" (${first.said})`);
    await page.waitForFunction(() => window.vdbmeshView.splatKind === 'fitted' || window.vdbmeshView.error, null, { polling: 100 });
    await page.waitForFunction(() => !window.vdbmeshView.splatBusy, null, { polling: 100 });
    const fitted = await driver.state();
    const fittedShot = await driver.shot('topology-preview-fitted');
    const fittedShare = foreground(fittedShot, BACKGROUND).share;
    checks.expect(!fitted.error && fittedShare > 0.05 && (await page.locator('#splat-kind').textContent()) === 'fitted',
      `then the fitted splats in its place (${fitted.splats} splats, ${(100 * fittedShare).toFixed(1)}% of the view), the figures saying "fitted"`);
    if (shotOfThePreview) {
      checks.expect(changedShare(preview, fittedShot) > 0.001, `and the picture changes (${(100 * changedShare(preview, fittedShot)).toFixed(2)}% of pixels)`);
    } else {
      console.log('the fit replaced the preview before its screenshot ended: the two pictures are not compared');
    }
    await page.waitForFunction(() => window.vdbmeshView.meshes > 0 || window.vdbmeshView.error, null, { polling: 100 });
    const later = await driver.state();
    checks.expect(!later.error && !later.preparing && later.splatKind === 'fitted', `then the coarse mesh and the slider (${later.level}, ${later.triangles} triangles)`);
    await page.close();
  } finally {
    checks.expect((await stopViewer(viewer.child)) === 0, 'view FILE.vdb (topology preview) stops cleanly on SIGINT (exit 0)');
  }
}

async function checkSplatsAlone(browser, options, splats, decode, checks, timeout) {
  const viewer = await startViewer(options.vdbmesh, [splats]);
  try {
    const page = await browser.newPage({ viewport: { width: 900, height: 700 } });
    page.on('pageerror', (error) => checks.expect(false, `no error in the page of the splat file alone: ${error.message}`));
    page.setDefaultTimeout(timeout);
    const driver = new PageDriver(page, options.out, decode);
    await page.goto(viewer.address);
    await page.waitForFunction(() => window.vdbmeshView.splatViews > 1 || window.vdbmeshView.error, null, { polling: 50 });
    const state = await driver.state();
    const drawn = foreground(await driver.shot('splat-file-alone'), BACKGROUND).share;
    const said = await page.locator('#figures').textContent();
    checks.expect(!state.error && state.splatMode && state.meshes === 0 && drawn > 0.05,
      `view FILE.splat alone shows its splats (${state.splats} splats, ${(100 * drawn).toFixed(1)}% of the view, meshes ${state.meshes}) ${state.error}`);
    checks.expect(said.includes('need the grid') && !(await page.locator('#scan-controls').isVisible()),
      `and says what needs the grid, with no iso slider ("${said.slice(0, 60)}…")`);
    const figures = await page.locator('#splat-figures').textContent();
    checks.expect(figures.includes(`finest level ${state.splatLevel}`) && (await page.locator('#detail').textContent()) === 'splats',
      `its figures name the level shown (${figures})`);
    await page.close();
  } finally {
    checks.expect((await stopViewer(viewer.child)) === 0, 'view FILE.splat stops cleanly on SIGINT (exit 0)');
  }
}

async function main() {
  const options = parseArguments(process.argv.slice(2));
  const chromiumPath = findChromium();
  if (!chromiumPath) skipOrFail('no Chromium (install Debian\'s chromium, or set CHROMIUM)');
  const { chromium } = createRequire(path.join(options.web, 'package.json'))('playwright-core');
  fs.mkdirSync(options.out, { recursive: true });
  const scratch = fs.mkdtempSync(path.join(os.tmpdir(), 'vdbmesh-browser-'));
  const checks = new Checks();
  const stages = new Stages();
  let viewer;
  let browser;
  try {
    let scan = options.scan;
    let driver;
    const timeout = Number(options.timeoutMs ?? 120000);
    await stages.time('start', async () => {
      if (!scan) {
        scan = path.join(scratch, 'torus.nii');
        execFileSync(options.vdbmesh, ['phantom', 'torus', '--size', '64', '--type', 'f32', '-o', scan]);
      }
      viewer = await startViewer(options.vdbmesh, [scan, ...options.viewArguments]);
      console.log(`vdbmesh view serves ${scan} at ${viewer.address}`);
      browser = await chromium.launch({ executablePath: chromiumPath, headless: true, args: CHROMIUM_FLAGS });  // a fresh profile each launch
      const page = await browser.newPage({ viewport: { width: 1000, height: 700 } });
      page.on('pageerror', (error) => checks.expect(false, `no error in the page: ${error.message}`));
      driver = new PageDriver(page, options.out, pngDecoder(options.web));
      page.setDefaultTimeout(timeout);  // SwiftShader draws millions of triangles slowly
      const started = Date.now();
      await page.goto(viewer.address);
      await driver.waitForFullMesh(0, timeout);
      console.log(`page loaded and showed the full mesh in ${Date.now() - started} ms`);
      await page.screenshot({ path: path.join(options.out, 'page.png') });
    });
    await stages.time('mesh', async () => {
      const solid = await checkModelDrawn(driver, checks);
      const remeshed = await checkIsoSlider(driver, checks, solid, options.isoTo === undefined ? undefined : Number(options.isoTo), timeout);
      await checkWireframe(driver, checks, remeshed);
      await checkClip(driver, checks);
      const { level, triangles } = await driver.state();
      await measureRotation(driver, checks, `the ${level} mesh, ${triangles} triangles`);
      await driver.click('#reset-view');
    });
    await stages.time('splats', async () => checkSplats(driver, checks, await driver.shot('solid-before-splats'), timeout));
    if (!options.scan || options.labelsMap) {
      await stages.time('labels', () => checkLabels(browser, options, scratch, driver.decode, checks, timeout));
    }
    if (!options.scan || options.latticeBox) {
      await stages.time('lattice', () => checkLattice(browser, options, driver.decode, checks, timeout));
    }
    if (!options.scan) await stages.time('splat file', () => checkSplatFile(browser, options, scratch, scan, driver.decode, checks, timeout));
    if (!options.scan) await stages.time('topology preview', () => checkTopologyPreview(browser, options, scratch, driver.decode, checks, timeout));
  } finally {
    await browser?.close();
    if (viewer) checks.expect((await stopViewer(viewer.child)) === 0, 'vdbmesh view stops cleanly on SIGINT (exit 0)');
    fs.rmSync(scratch, { recursive: true, force: true });
    stages.print();
  }
  console.log(`screenshots in ${options.out}`);
  process.exit(checks.failures === 0 ? 0 : 1);
}

main().catch((error) => {
  console.error(`FAIL: ${error.stack ?? error}`);
  process.exit(1);
});
