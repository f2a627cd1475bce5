// Screenshots of `vdbmesh view` for docs/ (issue 30): starts the server with the arguments
// after --, opens its page in Debian's headless Chromium (SwiftShader, 900 x 700 canvas), waits
// for the full budget's splats (the fitted ones when --fitted), saves the canvas and the page as
// OUT-whole.png and OUT-page.png, then, for each --close-up X,Y,STEPS given, pans the canvas
// point X,Y (fractions of its width and height) to the centre, wheels STEPS in, waits for the
// view to rest and saves OUT-close-N.png with the figures the page printed. A tool, not a test.
//
// node bench/view_screenshots.mjs --vdbmesh build/vdbmesh --web web --out build/shots/k3 [--fitted] [--close-up 0.42,0.31,12] -- view ARGS
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import { createRequire } from 'node:module';
import path from 'node:path';

const argv = process.argv.slice(2);
const split = argv.indexOf('--');
const own = argv.slice(0, split);
const option = (name) => own[own.indexOf(name) + 1];
const closeUps = own.flatMap((a, i) => (own[i - 1] === '--close-up' ? [a.split(',').map(Number)] : []));
const out = option('--out');
fs.mkdirSync(path.dirname(out), { recursive: true });
const { chromium } = createRequire(path.resolve(option('--web'), 'package.json'))('playwright-core');

const server = spawn(path.resolve(option('--vdbmesh')), [...argv.slice(split + 1), '--no-open', '--quiet', '--port', '0'],
  { stdio: ['ignore', 'pipe', 'inherit'] });
const address = await new Promise((resolve, reject) => {
  let printed = '';
  server.stdout.on('data', (chunk) => {
    const found = (printed += chunk).match(/at (http:\/\/\S+)/);
    if (found) resolve(found[1]);
  });
  server.on('exit', (code) => reject(new Error(`vdbmesh exited with ${code}`)));
});
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium', headless: true,
  args: ['--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
});
try {
  const page = await browser.newPage({ viewport: { width: 1200, height: 700 } });
  page.setDefaultTimeout(3600 * 1000);
  await page.goto(address);
  // At rest: the camera still for a second, the last view asked for drawn.
  const settled = async (before) => {
    await page.waitForFunction((b) => {
      const s = window.vdbmeshView;
      return s.error || (Date.now() - s.cameraMovedAt > 1000 && s.splatViews > b && !s.splatBusy && !s.moving);
    }, before, { polling: 200 });
    await page.evaluate(() => new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve))));
    const state = await page.evaluate(() => ({ ...window.vdbmeshView }));
    if (state.error) throw new Error(`the page reports: ${state.error}`);
    return state;
  };
  await page.waitForFunction(() => window.vdbmeshView.splatViews > 1 || window.vdbmeshView.error, null, { polling: 200 });
  if (own.includes('--fitted')) await page.waitForFunction(() => window.vdbmeshView.splatKind !== 'preview' || window.vdbmeshView.error, null, { polling: 500 });
  let state = await settled(0);
  const canvas = page.locator('#view canvas');
  const figures = async () => page.locator('#splat-figures').textContent();
  await canvas.screenshot({ path: `${out}-whole.png` });
  await page.screenshot({ path: `${out}-page.png` });
  console.log(JSON.stringify({ shot: `${out}-whole.png`, splats: state.splats, kind: state.splatKind, figures: await figures() }));
  const box = await canvas.boundingBox();
  for (const [n, [x, y, steps]] of closeUps.entries()) {
    // OrbitControls pans with the right button: the point under the cursor follows it.
    await page.mouse.move(box.x + x * box.width, box.y + y * box.height);
    await page.mouse.down({ button: 'right' });
    await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2, { steps: 10 });
    await page.mouse.up({ button: 'right' });
    for (let i = 0; i < steps; ++i) await page.mouse.wheel(0, -400);
    state = await settled(state.splatViews);
    await canvas.screenshot({ path: `${out}-close-${n + 1}.png` });
    console.log(JSON.stringify({ shot: `${out}-close-${n + 1}.png`, detail: state.detail, level: state.splatLevel,
      closeUpTriangles: state.closeUpTriangles, box: state.closeUpBox, figures: await figures() }));
  }
} finally {
  await browser.close();
  server.kill('SIGINT');
  await new Promise((resolve) => server.on('exit', resolve));
}
