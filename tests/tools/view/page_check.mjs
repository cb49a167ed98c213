// Loads a `semap view` page in headless Chromium (playwright-core driving the system's chromium) and reports
// what it shows, for tests/tools/view_test.cc:
//   node page_check.mjs --url URL --web-dir tools/view/web --screenshot PAGE.png --view-screenshot VIEW.png
//        [--expect-triangles N | --expect-ply MESH.ply] [--ready-file PATH] [--timeout-s S]
// Polls the page every 100 ms until it shows a mesh — with --expect-triangles, until the triangle count it
// shows equals N; with --expect-ply, until that file exists (a run writes it at its end) and the count equals
// the face count of its header — or the timeout. --ready-file is created once the page is connected and has
// the server's hello (a live test starts the run then). Then it saves the page (PAGE.png) and the 3D view alone,
// panels hidden (VIEW.png), and prints one JSON line: triangles shown, expected, the distinct counts seen over
// time, meshes received, frames drawn, source and status lines, seconds. Exit 0 when the count was reached (or
// nothing was expected and a mesh is shown), 3 on timeout, 2 on a usage or browser error.
import { createRequire } from 'node:module';
import fs from 'node:fs';
import path from 'node:path';

const args = {};
for (let i = 2; i < process.argv.length; i += 2) args[process.argv[i].replace(/^--/, '')] = process.argv[i + 1];
if (!args.url || !args['web-dir'] || !args.screenshot || !args['view-screenshot']) {
  console.error('usage: page_check.mjs --url URL --web-dir DIR --screenshot PAGE.png --view-screenshot VIEW.png ' +
                '[--expect-triangles N | --expect-ply MESH.ply] [--ready-file PATH] [--timeout-s S]');
  process.exit(2);
}
// playwright-core is a dev dependency of the page's package (tools/view/web/package.json, package-lock.json).
const require = createRequire(path.resolve(args['web-dir'], 'package.json'));
const { chromium } = require('playwright-core');
const timeoutMs = 1000 * Number(args['timeout-s'] || 60);
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

// The face count of a PLY header ("element face N"), or null while the file is not there.
function plyFaces(file) {
  if (!fs.existsSync(file)) return null;
  const head = fs.readFileSync(file).subarray(0, 4096).toString('latin1');
  const m = head.match(/\nelement face (\d+)\n/);
  return m ? Number(m[1]) : null;
}

const start = Date.now();
let browser;
try {
  browser = await chromium.launch({
    executablePath: process.env.SEMAP_CHROMIUM || '/usr/bin/chromium',
    headless: true,
    // WebGL without a GPU: SwiftShader, Chromium's software renderer.
    args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist'],
  });
  const page = await browser.newPage({ viewport: { width: 1000, height: 700 } });
  const logs = [];
  page.on('console', (m) => { if (m.type() === 'error') logs.push(`console: ${m.text()}`); });
  page.on('pageerror', (e) => logs.push(`pageerror: ${e.message}`));
  await page.goto(args.url, { timeout: timeoutMs });
  let expected = args['expect-triangles'] !== undefined ? Number(args['expect-triangles']) : null;
  const seen = [];
  let state = null;
  let reached = false;
  while (Date.now() - start < timeoutMs) {
    state = await page.evaluate(() => ({
      connected: window.semapView.connected,
      hello: window.semapView.hello !== null,
      meshes: window.semapView.meshesShown,
      triangles: Number(document.getElementById('triangles').dataset.count || 0),
    }));
    if (args['ready-file'] && state.connected && state.hello && !fs.existsSync(args['ready-file'])) {
      fs.writeFileSync(args['ready-file'], 'connected\n');
    }
    if (state.meshes > 0 && seen[seen.length - 1] !== state.triangles) seen.push(state.triangles);
    if (args['expect-ply'] && expected === null) expected = plyFaces(args['expect-ply']);
    const waiting = args['expect-ply'] && expected === null;
    if (state.meshes > 0 && !waiting && (expected === null || state.triangles === expected)) {
      reached = true;
      break;
    }
    await sleep(100);
  }
  // A few more frames so that the last mesh is on screen.
  const drawn = await page.evaluate(() => window.semapView.framesDrawn);
  await page.waitForFunction((n) => window.semapView.framesDrawn >= n + 5, drawn, { timeout: 10000 }).catch(() => {});
  await page.screenshot({ path: args.screenshot });
  await page.addStyleTag({ content: '.panel { display: none !important; }' });
  await page.waitForFunction((n) => window.semapView.framesDrawn >= n + 10, drawn, { timeout: 10000 }).catch(() => {});
  await page.screenshot({ path: args['view-screenshot'] });
  const shown = await page.evaluate(() => ({
    triangles: Number(document.getElementById('triangles').dataset.count || -1),
    meshes: window.semapView.meshesShown,
    frames: window.semapView.framesDrawn,
    has_error: window.semapView.hello ? window.semapView.hello.has_error : null,
    source: document.getElementById('source').textContent,
    status: document.getElementById('status').textContent,
    legend: document.getElementById('legend').textContent,
  }));
  Object.assign(shown, { expected, counts_seen: seen, reached, elapsed_s: (Date.now() - start) / 1000, logs });
  console.log(JSON.stringify(shown));
  await browser.close();
  process.exit(reached ? 0 : 3);
} catch (e) {
  console.error(`page_check: ${e.message}`);
  if (browser) await browser.close().catch(() => {});
  process.exit(2);
}
