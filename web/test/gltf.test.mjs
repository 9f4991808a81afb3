// meshdec's glTF surfaces against independent readers: Khronos's glTF
// validator (npm gltf-validator) finds no error in the .glb (Draco and
// plain) and the .gltf with its .bin, and three.js's GLTFLoader with its
// DRACOLoader loads them in chromium with meshdec's triangle count, normals
// and colours, and draws them (screenshots in the artifacts). Drawn by
// region, a part of two materials is each material's own surface, a
// primitive each with its material named as the region, whose triangles are
// those the WebAssembly decoder's cells give.
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdirSync, readFileSync, symlinkSync, writeFileSync, existsSync } from 'node:fs';
import { createRequire } from 'node:module';
import { basename, dirname, join } from 'node:path';
import { loadDecoder, webTestConfig } from './load_decoder.mjs';
import { DecoderSession } from '../page/decoder_session.js';
import { keptSurface } from '../page/cells.js';
import { launchBrowser, openPage, serve } from './browser.mjs';

const config = webTestConfig();
const validator = createRequire(import.meta.url)('gltf-validator');
const work = join(config.artifacts, 'gltf');
mkdirSync(work, { recursive: true });

function meshdec(stream, out, ...args) {
  execFileSync(config.meshdec, [stream, '-o', join(work, out), ...args], { stdio: ['ignore', 'pipe', 'pipe'] });
}
// The level's surface as meshdec writes it in OFF: its triangle count.
function surfaceTriangles(stream, level) {
  meshdec(stream, 'count.off', '--level', String(level));
  return Number(readFileSync(join(work, 'count.off'), 'utf8').split(/\s+/)[2]);
}

// Per region of the stream's finest level, the faces of exactly one of its
// cells (the viewer's cut of the cells of that region alone), summed.
async function regionTriangles(stream) {
  const session = new DecoderSession(await loadDecoder(config.dist));
  const { levels, error } = session.feed(readFileSync(stream));
  assert.equal(error, null);
  const l = levels.at(-1), names = session.regions.map((r) => r.name);
  session.dispose();
  let triangles = 0;
  names.forEach((_, r) => {
    const kept = l.cellRegions.map((x) => (x === r + 1 ? 1 : 0));
    triangles += keptSurface(l.cells, l.neighbors, kept).triangles.length / 3;
  });
  return { triangles, names };
}

const bunny = join(config.streams, 'bunny_10k.dtm');
const materials = join(config.source, 'tests', 'golden', 'two_materials.dtm');
const ct = join(config.streams, 'ct_torus.dtm');
const files = [
  { name: 'bunny_l0_draco.glb', stream: bunny, level: 0, args: [] },
  { name: 'bunny_l2_draco.glb', stream: bunny, level: 2, args: [] },
  { name: 'bunny_l0_plain.glb', stream: bunny, level: 0, args: ['--no-draco'] },
  { name: 'bunny_l1.gltf', stream: bunny, level: 1, args: [] },
  { name: 'bunny_l1_plain.gltf', stream: bunny, level: 1, args: ['--no-draco'] },
  { name: 'ct_value_draco.glb', stream: ct, level: 0, args: ['--color', 'value'] },
  { name: 'two_materials_region_draco.glb', stream: materials, level: 0, args: ['--color', 'region'] },
  { name: 'two_materials_region_plain.gltf', stream: materials, level: 0, args: ['--color', 'region', '--no-draco'] },
];
const byRegion = await regionTriangles(materials);
assert.deepEqual(byRegion.names, ['aluminium', 'steel']);
for (const f of files) {
  meshdec(f.stream, f.name, '--level', String(f.level), ...f.args);
  const region = f.args.includes('region');
  f.triangles = region ? byRegion.triangles : surfaceTriangles(f.stream, f.level);
  f.materials = region ? byRegion.names : [''];
}

for (const f of files) {
  test(`the glTF validator finds no error in ${f.name}`, async () => {
    const path = join(work, f.name);
    const report = await validator.validateBytes(new Uint8Array(readFileSync(path)), {
      uri: f.name,
      externalResourceFunction: async (uri) => new Uint8Array(readFileSync(join(dirname(path), decodeURIComponent(uri)))),
    });
    writeFileSync(`${path}.report.json`, JSON.stringify(report, null, 1));
    assert.equal(report.issues.numErrors, 0, JSON.stringify(report.issues.messages.filter((m) => m.severity === 0)));
    assert.equal(report.info.version, '2.0');
    const draco = !f.args.includes('--no-draco');
    assert.deepEqual(report.info.extensionsUsed ?? [], draco ? ['KHR_draco_mesh_compression'] : []);
    assert.deepEqual(report.info.extensionsRequired ?? [], draco ? ['KHR_draco_mesh_compression'] : []);
  });
}

let browser, server;
before(async () => {
  // A folder with three.js (its loaders and Draco's decoder) beside the files.
  const site = join(work, 'site');
  mkdirSync(site, { recursive: true });
  const three = join(site, 'three');
  if (!existsSync(three)) symlinkSync(join(config.source, 'web', 'node_modules', 'three'), three);
  for (const f of files) {
    for (const name of [f.name, f.name.replace(/\.gltf$/, '.bin')])
      if (existsSync(join(work, name)) && !existsSync(join(site, name))) symlinkSync(join(work, name), join(site, name));
  }
  writeFileSync(join(site, 'index.html'), `<!doctype html><meta charset="utf-8">
<link rel="icon" href="data:,"><style>html,body{margin:0}canvas{display:block}</style>
<canvas id="c" width="400" height="400"></canvas>
<script type="importmap">{"imports": {"three": "./three/build/three.module.js", "three/addons/": "./three/examples/jsm/"}}</script>
<script type="module">
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { DRACOLoader } from 'three/addons/loaders/DRACOLoader.js';
const loader = new GLTFLoader().setDRACOLoader(new DRACOLoader().setDecoderPath('./three/examples/jsm/libs/draco/'));
const renderer = new THREE.WebGLRenderer({ canvas: document.getElementById('c'), antialias: true });
window.show = async (url) => {
  const gltf = await loader.loadAsync(url);
  let triangles = 0, vertices = 0, attributes = [], materials = [];
  gltf.scene.traverse((o) => {
    if (!o.isMesh) return;
    triangles += o.geometry.index.count / 3;
    vertices += o.geometry.attributes.position.count;
    attributes = Object.keys(o.geometry.attributes).sort();
    materials.push(o.material.name);
  });
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0xffffff);
  scene.add(gltf.scene, new THREE.HemisphereLight(0xffffff, 0x404040, 2));
  const box = new THREE.Box3().setFromObject(gltf.scene), centre = box.getCenter(new THREE.Vector3());
  const camera = new THREE.PerspectiveCamera(30, 1, 0.01, 1e6);
  camera.position.copy(centre).add(new THREE.Vector3(0, 0, 2.2 * box.getSize(new THREE.Vector3()).length()));
  camera.lookAt(centre);
  camera.near = camera.position.distanceTo(centre) / 100;
  camera.far = camera.position.distanceTo(centre) * 10;
  camera.updateProjectionMatrix();
  renderer.render(scene, camera);
  // The share of the picture drawn in a colour: neither the white
  // background nor black (a material that reflects nothing here).
  const gl = renderer.getContext(), pixels = new Uint8Array(4 * 400 * 400);
  gl.readPixels(0, 0, 400, 400, gl.RGBA, gl.UNSIGNED_BYTE, pixels);
  let coloured = 0;
  for (let i = 0; i < pixels.length; i += 4) {
    const high = Math.max(pixels[i], pixels[i + 1], pixels[i + 2]), low = Math.min(pixels[i], pixels[i + 1], pixels[i + 2]);
    if (high > 40 && low < 245) ++coloured;
  }
  return { triangles, vertices, attributes, materials, coloured: coloured / (400 * 400) };
};
window.ready = true;
</script>`);
  server = await serve({ ...config, dist: site });
  browser = await launchBrowser();
});
after(async () => {
  await browser?.close();
  server?.close();
});

for (const f of files) {
  test(`three.js's GLTFLoader and DRACOLoader load ${f.name} in chromium`, async () => {
    const page = await openPage(browser, { width: 400, height: 400 });
    try {
      await page.goto(`${server.url}index.html`);
      await page.waitForFunction(() => window.ready === true);
      const loaded = await page.evaluate((url) => window.show(url), f.name);
      assert.equal(loaded.triangles, f.triangles);
      assert.deepEqual(loaded.attributes, ['color', 'normal', 'position']);
      assert.deepEqual(loaded.materials, f.materials, 'a primitive per region, its material named as the region');
      assert.ok(loaded.coloured > 0.05, `${loaded.coloured} of the picture drawn in a colour`);
      assert.deepEqual(page.problems, []);
      await page.screenshot({ path: join(work, `${basename(f.name)}.png`) });
    } finally {
      await page.close();
    }
  });
}
