// foldcast's .glb files in the viewers product pages use, in headless Chromium: three.js's
// GLTFLoader (with its meshopt decoder) loads a static garment and an animation, whose
// vertex positions match foldcast's own (OBJ, PC2) within the quantization error and whose
// animation plays; Google's <model-viewer> shows an exported scene garment whose silhouette
// matches foldcast's EGL preview of the same scene from the same camera (IoU >= 0.9).
import { execFileSync } from 'node:child_process';
import { mkdirSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { parseArgs } from 'node:util';
import { launchChromium } from './chromium.mjs';
import { origin, serveLocally } from './local_site.mjs';

const { values: args } = parseArgs({ options: { foldcast: { type: 'string' }, chromium: { type: 'string' }, tmp: { type: 'string' } } });
rmSync(args.tmp, { recursive: true, force: true });
const files = join(args.tmp, 'files');
mkdirSync(files, { recursive: true });
const modules = join(dirname(fileURLToPath(import.meta.url)), '..', 'node_modules');
const foldcast = (...a) => execFileSync(args.foldcast, a, { encoding: 'utf8', stdio: ['ignore', 'pipe', 'inherit'] });
const at = (name) => join(files, name);

// The garments: a static denim panel, and 16 frames of the folds forming with sway.
foldcast('drape', '--grid', '24x32', '--look', 'denim', '-q', '-o', at('static.glb'));
foldcast('drape', '--grid', '24x32', '--look', 'denim', '-q', '-o', at('static.obj'));
const anim = ['drape', '--grid', '24x32', '--frames', '16', '--fps', '24', '--sway-m', '0.03', '--look', 'satin', '-q'];
const glbReport = JSON.parse(foldcast(...anim, '--json', '-o', at('anim.glb'))).glb;
foldcast(...anim, '-o', at('anim.pc2'));
const objPositions = readFileSync(at('static.obj'), 'utf8').split('\n').filter((l) => l.startsWith('v '))
  .flatMap((l) => l.split(/\s+/).slice(1, 4).map(Number));
const pc2 = readFileSync(at('anim.pc2'));
const pc2Vertices = pc2.readInt32LE(16), pc2Frames = pc2.readInt32LE(28);
const pc2Frame = (f) => Array.from(new Float32Array(pc2.buffer.slice(pc2.byteOffset + 32 + f * pc2Vertices * 12,
  pc2.byteOffset + 32 + (f + 1) * pc2Vertices * 12)));

// Scenes seen by a fixed camera, exported and previewed: the silhouettes must agree.  The
// folded garment is a still (float attributes); the swaying one a compressed morph-target
// animation, shown by both at its frame 0 (the folds not yet formed).
const camera = { position: [0.35, -0.25, 1.55], target: [0.0, -0.38, 0.0], fov: 30 };
const scene = (name, garmentKeys) => writeFileSync(at(`${name}.toml`), `look = "velvet"
[garment]
source = "drape"
grid = [40, 52]
${garmentKeys}
[camera]
position = [${camera.position}]
target = [${camera.target}]
fov_deg = ${camera.fov}
[backdrop]
kind = "cyclorama"
transparent = true
[supports]
kind = "none"
[output]
width = 400
height = 300
`);
const viewerScenes = ['folded', 'sway'];
scene('folded', '');
scene('sway', 'animation_frames = 8\nsway_amplitude_m = 0.03');
for (const name of viewerScenes) {
  foldcast('export', at(`${name}.toml`), '-q', '-o', at(`${name}.glb`));
  foldcast('preview', at(`${name}.toml`), '--quiet', '-o', at(`${name}-preview.png`));
}

const page3 = `<!doctype html><html><body style="margin:0;background:#000">
<script type="importmap">{"imports":{"three":"/three/build/three.module.js","three/addons/":"/three/examples/jsm/"}}</script>
<script type="module">
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { MeshoptDecoder } from 'three/addons/libs/meshopt_decoder.module.js';
const loader = new GLTFLoader().setMeshoptDecoder(MeshoptDecoder);
const find = (root) => { let m = null; root.traverse((o) => { if (o.isMesh && !m) m = o; }); return m; };
// World positions of every vertex as three.js places them (morph targets applied).
const positions = (mesh) => {
  mesh.updateWorldMatrix(true, false);
  const v = new THREE.Vector3(), out = [];
  for (let i = 0; i < mesh.geometry.attributes.position.count; i++) {
    mesh.getVertexPosition(i, v).applyMatrix4(mesh.matrixWorld);
    out.push(v.x, v.y, v.z);
  }
  return out;
};
window.loadStatic = async (url) => {
  const gltf = await loader.loadAsync(url);
  const mesh = find(gltf.scene);
  const m = mesh.material;
  return { positions: positions(mesh), material: { type: m.type, name: m.name, map: !!m.map, normalMap: !!m.normalMap,
    sheen: m.sheen, anisotropy: m.anisotropy, side: m.side, repeat: m.map ? m.map.repeat.toArray() : null } };
};
window.loadAnimation = async (url, frames, fps) => {
  const gltf = await loader.loadAsync(url);
  const mesh = find(gltf.scene);
  const mixer = new THREE.AnimationMixer(gltf.scene);
  // Once through, held at the end: setTime(duration) is then the last frame, not frame 0 again.
  const action = mixer.clipAction(gltf.animations[0]).setLoop(THREE.LoopOnce, 1).play();
  action.clampWhenFinished = true;
  const byFrame = [];
  for (let f = 0; f < frames; f++) {
    mixer.setTime(f / fps);
    byFrame.push(positions(mesh));
  }
  // Played in real time: the frame on show (the target with the largest weight) advances.
  const renderer = new THREE.WebGLRenderer({ antialias: false });
  renderer.setSize(320, 240);
  document.body.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  scene.add(gltf.scene, new THREE.HemisphereLight(0xffffff, 0x404040, 3));
  const cam = new THREE.PerspectiveCamera(35, 320 / 240, 0.01, 10);
  cam.position.set(0, -0.4, 1.6);
  action.setLoop(THREE.LoopRepeat, Infinity).reset().play();
  mixer.setTime(0);
  const shown = new Set(), start = performance.now();
  let last = start;
  let ticks = 0;
  await new Promise((done) => {
    const tick = () => {
      const now = performance.now();
      mixer.update((now - last) / 1000);
      last = now;
      renderer.render(scene, cam);
      const w = mesh.morphTargetInfluences;
      let best = -1, bestW = 0.5;
      w.forEach((x, i) => { if (x > bestW) { bestW = x; best = i; } });
      shown.add(best + 1);
      // At least 0.6 s and 12 rendered frames: a slow software renderer under load
      // still shows several animation frames.
      if (++ticks < 12 || now - start < 600) requestAnimationFrame(tick); else done();
    };
    requestAnimationFrame(tick);
  });
  const gl = renderer.getContext(), px = new Uint8Array(320 * 240 * 4);
  gl.readPixels(0, 0, 320, 240, gl.RGBA, gl.UNSIGNED_BYTE, px);
  let lit = 0;
  for (let i = 0; i < px.length; i += 4) lit += px[i] + px[i + 1] + px[i + 2] > 0;
  return { byFrame, targets: mesh.morphTargetInfluences.length, framesShown: shown.size, litPixels: lit,
    duration: gltf.animations[0].duration };
};
window.ready = true;
</script></body></html>`;

const d = camera.position.map((x, i) => x - camera.target[i]);
const radius = Math.hypot(...d);
const theta = Math.atan2(d[0], d[2]) * 180 / Math.PI, phi = Math.acos(d[1] / radius) * 180 / Math.PI;
const pageMv = `<!doctype html><html><body style="margin:0;background:transparent">
<script type="module">
import '/model-viewer/model-viewer.min.js';
// model-viewer bundles meshoptimizer's decoder and enables it once a script at this
// location has loaded (by default one from a CDN, which this test cannot reach).
customElements.get('model-viewer').meshoptDecoderLocation = '/meshopt-enable.js';
const mv = document.createElement('model-viewer');
mv.style.cssText = 'width:400px;height:300px;display:block;background-color:transparent';
mv.setAttribute('interaction-prompt', 'none');
mv.setAttribute('camera-target', '${camera.target.map((x) => `${x}m`).join(' ')}');
mv.setAttribute('camera-orbit', '${theta}deg ${phi}deg ${radius}m');
mv.setAttribute('min-camera-orbit', 'auto auto 0.01m');
mv.setAttribute('max-camera-orbit', 'auto auto 100m');
mv.setAttribute('field-of-view', '${camera.fov}deg');
mv.setAttribute('min-field-of-view', '1deg');
mv.setAttribute('max-field-of-view', '170deg');
mv.setAttribute('interpolation-decay', '1000');
mv.addEventListener('load', () => { mv.jumpCameraToGoal(); setTimeout(() => { window.mvLoaded = true; }, 500); });
mv.addEventListener('error', (e) => { window.mvError = String(e.detail?.type || e.type); });
const name = new URLSearchParams(location.search).get('scene');
mv.src = \`/files/\${name}.glb\`;
document.body.appendChild(mv);
// Alpha masks of the viewer's frame and of foldcast's preview, and their IoU.
window.silhouettes = async () => {
  const toImage = (src) => new Promise((ok, bad) => { const i = new Image(); i.onload = () => ok(i); i.onerror = bad; i.src = src; });
  const mask = (img) => {
    const c = document.createElement('canvas'); c.width = 400; c.height = 300;
    const g = c.getContext('2d'); g.drawImage(img, 0, 0, 400, 300);
    const d = g.getImageData(0, 0, 400, 300).data, m = new Uint8Array(400 * 300);
    for (let i = 0; i < m.length; i++) m[i] = d[4 * i + 3] > 127;
    return m;
  };
  const viewer = mask(await toImage(mv.toDataURL('image/png')));
  const preview = mask(await toImage(\`/files/\${name}-preview.png\`));
  let both = 0, either = 0, a = 0, b = 0;
  for (let i = 0; i < viewer.length; i++) { both += viewer[i] & preview[i]; either += viewer[i] | preview[i]; a += viewer[i]; b += preview[i]; }
  return { iou: both / either, viewerPixels: a, previewPixels: b, png: mv.toDataURL('image/png') };
};
</script></body></html>`;

const { browser, close } = await launchChromium(args.chromium, args.tmp);
let passed = 0, failed = 0;
const check = (ok, what) => { ok ? passed++ : failed++; console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`); };
const maxDiff = (a, b) => a.reduce((m, x, i) => Math.max(m, Math.abs(x - b[i])), 0);
try {
  const page = await browser.newPage();
  page.on('console', (m) => { if (!m.text().includes('GL Driver Message')) console.log(`page: ${m.text()}`); });
  page.on('pageerror', (e) => console.log(`page error: ${e.message}`));
  const mounts = { '/three/': join(modules, 'three') + '/', '/model-viewer/': join(modules, '@google/model-viewer/dist') + '/', '/files/': files + '/' };
  await serveLocally(page, mounts, { '/three.html': page3, '/model-viewer.html': pageMv, '/meshopt-enable.js': '' });

  await page.goto(`${origin}/three.html`);
  await page.waitForFunction(() => window.ready, { timeout: 30000 });
  const s = await page.evaluate(() => window.loadStatic('/files/static.glb'));
  check(s.positions.length === objPositions.length && maxDiff(s.positions, objPositions) < 1e-5,
    `static garment: ${s.positions.length / 3} vertices, positions equal the OBJ's (max difference ${maxDiff(s.positions, objPositions).toExponential(2)} m)`);
  check(s.material.type === 'MeshPhysicalMaterial' && s.material.name === 'denim' && s.material.map && s.material.normalMap &&
    s.material.sheen > 0 && s.material.anisotropy > 0 && s.material.side === 2,
    `denim material: ${JSON.stringify(s.material)}`);

  const a = await page.evaluate((f, fps) => window.loadAnimation('/files/anim.glb', f, fps), pc2Frames, 24);
  const tolerance = glbReport.max_position_error_m + 1e-6;
  let worst = 0;
  for (let f = 0; f < pc2Frames; f++) worst = Math.max(worst, maxDiff(a.byFrame[f], pc2Frame(f)));
  check(a.targets === pc2Frames - 1 && Math.abs(a.duration - (pc2Frames - 1) / 24) < 1e-4,
    `animation: ${a.targets} morph targets, ${a.duration.toFixed(3)} s`);
  check(worst <= tolerance, `every frame's positions within the quantization error: max ${worst.toExponential(3)} m <= ${tolerance.toExponential(3)} m`);
  check(a.framesShown >= 4 && a.litPixels > 1000, `played in real time: ${a.framesShown} frames shown, ${a.litPixels} lit pixels`);

  for (const name of viewerScenes) {
    await page.goto(`${origin}/model-viewer.html?scene=${name}`);
    await page.waitForFunction(() => window.mvLoaded || window.mvError, { timeout: 60000, polling: 100 });
    const error = await page.evaluate(() => window.mvError);
    check(!error, `model-viewer loaded the exported ${name} scene (${error ?? 'no error'})`);
    if (error) continue;
    const sil = await page.evaluate(() => window.silhouettes());
    const shot = join(args.tmp, `model-viewer-${name}.png`);
    writeFileSync(shot, Buffer.from(sil.png.split(',')[1], 'base64'));
    check(sil.iou >= 0.9, `${name}: silhouette IoU with the EGL preview ${sil.iou.toFixed(4)} >= 0.9 (${sil.viewerPixels} vs ${sil.previewPixels} pixels; ${shot})`);
  }
} catch (e) {
  failed++;
  console.log(`FAIL ${e.stack || e}`);
} finally {
  await close();
}
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
