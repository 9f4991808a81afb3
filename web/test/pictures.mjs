// The README's pictures, taken by the viewer itself: per model, the input's
// own surface (an OFF file) beside every level of its stream, finest first,
// each panel a screenshot of the page's canvas with its figures underneath,
// laid out side by side in one PNG by the browser.
import { readFileSync, writeFileSync } from 'node:fs';
import { openPage, serve, waitForEnd } from './browser.mjs';

const kPanel = 300;

// Screenshots of every level of `stream` (and of `surface`, an OFF path, if
// given), as PNG buffers with their captions.
export async function levelPanels(browser, config, { stream, surface, camera }) {
  const server = await serve(config, stream);
  const page = await openPage(browser, { width: kPanel, height: kPanel });
  const panels = [];
  try {
    if (surface) {
      await page.route('**/input.off', (route) => route.fulfill({ body: readFileSync(surface), contentType: 'text/plain' }));
      await page.goto(`${server.url}?surface=input.off&ui=0&camera=${camera}`);
      const state = await waitForEnd(page);
      if (state.status !== 'done') throw new Error(`${surface}: ${state.error}`);
      panels.push({ png: await page.screenshot(), caption: ['input surface', `${state.trianglesDrawn.toLocaleString('en-US')} triangles`] });
    }
    await page.goto(`${server.url}?stream=stream.dtm&ui=0&camera=${camera}`);
    const state = await waitForEnd(page);
    if (state.status !== 'done') throw new Error(`${stream}: ${state.error}`);
    for (let index = state.levels.length - 1; index >= 0; --index) {
      const frames = await page.evaluate(() => window.dtmViewer.frames);
      await page.evaluate((i) => {
        const slider = document.getElementById('level');
        slider.value = String(i);
        slider.dispatchEvent(new Event('input'));
      }, index);
      await page.waitForFunction((f) => window.dtmViewer.frames > f, frames);
      const now = await page.evaluate(() => JSON.parse(JSON.stringify(window.dtmViewer)));
      const l = state.levels[index];
      panels.push({
        png: await page.screenshot(),
        caption: [`level ${l.level}`, `${l.vertices.toLocaleString('en-US')} vertices, ${l.tetrahedra.toLocaleString('en-US')} tetrahedra`,
                  `${now.trianglesDrawn.toLocaleString('en-US')} triangles, ${(l.bytes / 1000).toFixed(1)} KB`],
      });
    }
  } finally {
    await page.close();
    server.close();
  }
  return panels;
}

// Lays `panels` out in one row with a title, and writes the PNG to `path`.
export async function composePicture(browser, title, panels, path) {
  const page = await openPage(browser, { width: panels.length * kPanel, height: kPanel + 120 });
  try {
    const cells = panels.map((p) => `<figure><img src="data:image/png;base64,${p.png.toString('base64')}">
      <figcaption>${p.caption.map((line, i) => (i ? line : `<b>${line}</b>`)).join('<br>')}</figcaption></figure>`);
    await page.setContent(`<!doctype html><style>
      body { margin: 0; font: 13px/1.35 sans-serif; color: #222; background: #fff; }
      h1 { font-size: 14px; margin: 8px 10px 0; font-weight: 600; }
      .row { display: flex; } figure { margin: 0; width: ${kPanel}px; text-align: center; }
      img { display: block; width: ${kPanel}px; height: ${kPanel}px; }
      </style><h1>${title}</h1><div class="row">${cells.join('')}</div>`);
    const row = await page.$('body');
    writeFileSync(path, await row.screenshot());
  } finally {
    await page.close();
  }
}
