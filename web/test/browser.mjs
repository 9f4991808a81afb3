// Debian's chromium, driven by Playwright (playwright-core: it never
// downloads a browser), and the project's own server (scripts/serve.py).
import { spawn } from 'node:child_process';
import { join } from 'node:path';
import { chromium } from 'playwright-core';

// WebGL without a GPU: SwiftShader, which Chromium no longer falls back to
// on its own. Playwright already passes --no-sandbox (as root) and the flags
// that keep Chromium off the network.
export async function launchBrowser() {
  return chromium.launch({
    executablePath: process.env.DTM_CHROMIUM || '/usr/bin/chromium',
    args: ['--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--disable-dev-shm-usage'],
  });
}

// Serves `dist` (and `stream` as /stream.dtm, throttled to `rate` if given)
// on a free port; resolves to {url, close()}. `extra`: more serve.py options.
export function serve(config, stream, rate, extra = []) {
  const args = [join(config.source, 'scripts', 'serve.py'), config.dist];
  if (stream) args.push(stream);
  if (rate) args.push('--rate', rate);
  args.push(...extra);
  const server = spawn('python3', args, { stdio: ['ignore', 'pipe', 'inherit'] });
  return new Promise((resolve, reject) => {
    server.once('error', reject);
    server.once('exit', (code) => reject(new Error(`serve.py exited with ${code}`)));
    server.stdout.once('data', (line) => {
      const url = String(line).trim().replace(/\?.*$/, '');
      resolve({ url, close: () => server.kill() });
    });
  });
}

// A page that records its errors: uncaught exceptions, console errors,
// failed requests (but the ones a test provokes), crashes.
export async function openPage(browser, { width = 900, height = 700 } = {}) {
  const page = await browser.newPage({ viewport: { width, height } });
  page.problems = [];
  page.on('pageerror', (e) => page.problems.push(`page error: ${e.message}`));
  page.on('crash', () => page.problems.push('the page crashed'));
  page.on('console', (m) => { if (m.type() === 'error') page.problems.push(`console error: ${m.text()}`); });
  return page;
}

export async function waitForEnd(page, timeout = 120_000) {
  await page.waitForFunction(() => ['done', 'truncated', 'error'].includes(window.dtmViewer?.status), null, { timeout });
  // ... and for the level shown to be on the screen.
  await page.waitForFunction(() => window.dtmViewer.shown === null || window.dtmViewer.rendered === window.dtmViewer.shown,
                             null, { timeout });
  return page.evaluate(() => JSON.parse(JSON.stringify(window.dtmViewer)));
}

// The canvas scaled to 200 x 150: its pixels' RGBA bytes.
export async function canvasPixels(page) {
  return Uint8Array.from(await page.evaluate(() => {
    const canvas = document.getElementById('canvas');
    const probe = document.createElement('canvas');
    probe.width = 200, probe.height = 150;
    const context = probe.getContext('2d');
    context.drawImage(canvas, 0, 0, probe.width, probe.height);
    return Array.from(context.getImageData(0, 0, probe.width, probe.height).data);
  }));
}

// The share of the canvas's pixels for which `is(r, g, b)` holds.
export async function pixelShare(page, is) {
  const pixels = await canvasPixels(page);
  let count = 0;
  for (let i = 0; i < pixels.length; i += 4) if (is(pixels[i], pixels[i + 1], pixels[i + 2])) ++count;
  return count / (pixels.length / 4);
}

// How much of the canvas is drawn (not the white background): a share.
export async function drawnShare(page) {
  return pixelShare(page, (r, g, b) => r + g + b < 3 * 245);
}
