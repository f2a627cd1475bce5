// The wall time from starting `vdbmesh view FILE` to its first picture in a browser (issue 30:
// "the whole model on the page within 5 s"), and the server's peak memory. Starts the server
// under /usr/bin/time, opens its page in Debian's headless Chromium (SwiftShader, 900 x 700
// canvas) as soon as it serves, and waits for the page's first mesh on screen; then,
// with --splats, ticks Display > splats and waits for the first splats on screen. Prints JSON.
// A benchmark, not a test.
//
// With --lattice, the server is `vdbmesh lattice ARGUMENTS --view` (the arguments after --) and
// the first picture is its first splats.
//
// With --frame-time, once the first splats (or mesh) and the full budget's splats are drawn, drags
// across the view as the browser test does and reports the page's frame time while rotating
// (View > frame time: the median of the last 30 frames drawn while the camera moved).
//
// A .vdb without a splat file first shows its topology preview ("splat_kind": "preview"); with
// --until-fitted the bench then waits for the fitted splats in its place and reports when.
//
// node bench/view_first_picture.mjs --vdbmesh build/vdbmesh --web web FILE [--splats] [--frame-time] [--until-fitted] [-- view arguments]
// node bench/view_first_picture.mjs --vdbmesh build/vdbmesh --web web --lattice -- gyroid --period 64 --thickness 4 --box 4096 --voxel 1
import { spawn } from 'node:child_process';
import { createRequire } from 'node:module';
import path from 'node:path';

const argv = process.argv.slice(2);
const split = argv.indexOf('--');
const own = split < 0 ? argv : argv.slice(0, split);
const option = (name) => own[own.indexOf(name) + 1];
const file = own.filter((a, i) => !a.startsWith('--') && !['--vdbmesh', '--web'].includes(own[i - 1]))[0];
const { chromium } = createRequire(path.resolve(option('--web'), 'package.json'))('playwright-core');

/// Drags across the canvas (15 steps right, 15 back) and returns the page's frame time, the
/// drag's seconds and whether the server's background work (fit, preparation) was under way
/// before and after it (it pauses while the camera moves).
async function rotate(page) {
  await page.waitForFunction(() => window.vdbmeshView.splatViews > 1 || window.vdbmeshView.meshes > 0, null, { polling: 100 });
  const preparingBefore = await page.evaluate(() => window.vdbmeshView.preparing);
  const dragStarted = Date.now();
  const box = await page.locator('#view canvas').boundingBox();
  const y = box.y + box.height / 2;
  await page.mouse.move(box.x + box.width * 0.3, y);
  await page.mouse.down();
  await page.mouse.move(box.x + box.width * 0.7, y, { steps: 15 });
  await page.mouse.move(box.x + box.width * 0.3, y, { steps: 15 });
  await page.mouse.up();
  await page.evaluate(() => new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve))));
  const drag_s = Number(((Date.now() - dragStarted) / 1000).toFixed(2));
  const state = await page.evaluate(() => ({ ...window.vdbmeshView }));
  return { ms: state.frameMs, frames: state.frameSamples, triangles: state.frameTriangles, drag_s,
    preparing: [preparingBefore, state.preparing], shown: await page.locator('#frame-time').textContent() };
}

const started = Date.now();
const seconds = () => Number(((Date.now() - started) / 1000).toFixed(2));
const lattice = own.includes('--lattice');
const command = lattice ? ['lattice', '--view'] : ['view', file];
const server = spawn('/usr/bin/time', ['-f', 'peak_kb %M', path.resolve(option('--vdbmesh')), ...command, '--no-open', '--quiet',
  '--port', '0', ...(split < 0 ? [] : argv.slice(split + 1))], { stdio: ['ignore', 'pipe', 'pipe'], detached: true });
let errors = '';
server.stderr.on('data', (chunk) => (errors += chunk));
const address = await new Promise((resolve, reject) => {
  let printed = '';
  server.stdout.on('data', (chunk) => {
    const found = (printed += chunk).match(/at (http:\/\/\S+)/);
    if (found) resolve(found[1]);
  });
  server.on('exit', (code) => reject(new Error(`vdbmesh view exited with ${code}: ${errors}`)));
});
const report = { file: lattice ? `lattice ${argv.slice(split + 1).join(' ')}` : file, serving_s: seconds() };
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium', headless: true,
  args: ['--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
});
try {
  const page = await browser.newPage({ viewport: { width: 1200, height: 700 } });  // the panel takes 300
  page.setDefaultTimeout(3600 * 1000);
  const pageOpened = Date.now();
  await page.goto(address);
  // Checked at each animation frame, and the time taken as soon as the answer arrives: the page
  // asks for the full budget's splats two frames after its first picture, and their upload and
  // drawing then hold its thread (a timed poll and a second evaluate() waited behind them).
  const seen = await page.waitForFunction(() => {
    const s = window.vdbmeshView;
    return (s.meshes > 0 || s.splatViews > 0 || s.error) && { ...s };
  }, null, { polling: 'raf' });
  const firstPictureS = seconds();
  const state = await seen.jsonValue();
  const picture = state.splatViews > 0 ? `${state.splats} splats, finest level ${state.splatLevel}` : `${state.level} mesh, ${state.triangles} triangles`;
  Object.assign(report, { first_picture_s: firstPictureS, first_picture: picture, error: state.error || undefined });
  if (state.splatViews > 0) Object.assign(report, { splat_kind: state.splatKind, splat_figures: await page.locator('#splat-figures').textContent() });
  // Where the time after serving went: the page's requests, in seconds from the navigation.
  report.page_s = await page.evaluate(() => Object.fromEntries([
    ['dom_ready', performance.timing.domContentLoadedEventEnd - performance.timing.navigationStart],
    ...performance.getEntriesByType('resource').filter((e) => e.name.includes('/api/') || e.name.endsWith('.js'))
      .slice(0, 6).map((e) => [`${new URL(e.name).pathname} ${e.startTime.toFixed(0)}`, e.responseEnd - e.startTime]),
  ].map(([k, v]) => [k, Number((v / 1000).toFixed(2))])));
  report.page_opened_s = Number(((pageOpened - started) / 1000).toFixed(2));
  // The page's own clock: when its first splats were drawn (the polling above can lag while
  // SwiftShader holds the page's thread).
  if (state.firstSplatsMs) report.first_splats_by_page_s = Number((report.page_opened_s + state.firstSplatsMs / 1000).toFixed(2));
  if (own.includes('--frame-time')) report.frame_time = await rotate(page);
  if (own.includes('--until-fitted')) {
    await page.waitForFunction(() => window.vdbmeshView.splatKind === 'fitted' || window.vdbmeshView.error, null, { polling: 500 });
    const fitted = await page.evaluate(() => ({ ...window.vdbmeshView }));
    Object.assign(report, { fitted_splats_s: seconds(), fitted_splats: fitted.splats, error: fitted.error || undefined });
  }
  if (own.includes('--splats')) {
    await page.locator('#splats').click();
    await page.waitForFunction(() => window.vdbmeshView.splatViews > 0 || window.vdbmeshView.error, null, { polling: 100 });
    const shown = await page.evaluate(() => ({ ...window.vdbmeshView }));
    Object.assign(report, { first_splats_s: seconds(), splats: shown.splats, close_up_triangles: shown.closeUpTriangles, error: shown.error || undefined });
  }
} finally {
  await browser.close();
  process.kill(-server.pid, 'SIGINT');  // to vdbmesh too: GNU time ignores it while it waits
  await new Promise((resolve) => server.on('exit', resolve));
}
const peak = errors.match(/peak_kb (\d+)/);
report.peak_mb = peak ? Math.round(Number(peak[1]) / 1024) : null;
console.log(JSON.stringify(report, null, 1));
