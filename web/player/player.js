// foldcast's browser player: streams an .fca file with fetch(), decodes it with the codec
// library compiled to WebAssembly (fca_stream.js) and shows every frame as soon as the
// bytes so far allow, sharpening as packets arrive (docs/player.md).
//   index.html?file=URL      any .fca URL (works from a static web server)
//   index.html               `foldcast serve`: the files it lists (api/files), first one shown
//   &look=NAME               the look whose base colour the cloth takes (looks.json)
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/OrbitControls.js';
import { FcaStream } from './fca_stream.js';

const $ = (id) => document.getElementById(id);
const params = new URLSearchParams(location.search);

// What the page measured, in ms since navigation start; read by the tests and benchmarks.
const stats = {
  url: null, fetchStartMs: null, totalBytes: null, bytes: 0, headerMs: null, firstFrameMs: null, bytesAtFirstFrame: null,
  allPlayableMs: null, completeMs: null, downloadDoneMs: null, error: null, framesShown: 0,
};
const state = { stream: null, playing: params.get('paused') === null, time_s: 0, shown: -1, shownPackets: -1, geometry: null };
window.foldcastPlayer = {
  stats,
  pause() { setPlaying(false); },
  seek(t) { setPlaying(false); $('scrub').value = String(t); state.time_s = t / (state.stream?.fps || 30); },
  // The frame on screen: index, packets it was decoded from, and its float32 xyz bytes (base64).
  shownFrame() {
    const pos = state.geometry?.getAttribute('position');
    if (!pos) return null;
    const bytes = new Uint8Array(pos.array.buffer, pos.array.byteOffset, pos.array.byteLength);
    let text = '';
    for (let i = 0; i < bytes.length; i += 0x8000) text += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
    return { index: state.shown, packets: state.shownPackets, complete: state.status?.complete ?? false, base64: btoa(text) };
  },
};

const now = () => performance.now();
const fmtBytes = (n) => (n >= 1e6 ? `${(n / 1e6).toFixed(2)} MB` : `${(n / 1e3).toFixed(1)} kB`);

// --- three.js scene ---------------------------------------------------------------
const renderer = new THREE.WebGLRenderer({ canvas: $('view'), antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0x30353d);
const camera = new THREE.PerspectiveCamera(35, 1, 0.01, 100);
const controls = new OrbitControls(camera, renderer.domElement);
scene.add(new THREE.HemisphereLight(0xffffff, 0x404040, 1.2));
const sun = new THREE.DirectionalLight(0xffffff, 2.0);
sun.position.set(1, 2, 3);
scene.add(sun);
const material = new THREE.MeshStandardMaterial({ color: 0xb8442e, roughness: 0.85, side: THREE.DoubleSide });

function resize() {
  const w = window.innerWidth, h = window.innerHeight;
  renderer.setSize(w, h, false);
  camera.aspect = w / h;
  camera.updateProjectionMatrix();
}
window.addEventListener('resize', resize);
resize();

function setPlaying(on) {
  state.playing = on;
  $('play').textContent = on ? 'pause' : 'play';
}
$('play').addEventListener('click', () => setPlaying(!state.playing));
$('scrub').addEventListener('input', () => {
  setPlaying(false);
  state.time_s = Number($('scrub').value) / (state.stream?.fps || 30);
});

function showError(message) {
  stats.error = message;
  $('error').hidden = false;
  $('error').textContent = message;
}

// --- looks: base colours from looks.json (`foldcast looks --json` at build time) ---
async function loadLooks() {
  try {
    const looks = (await (await fetch('looks.json')).json()).looks;
    for (const look of looks) {
      const option = new Option(look.name, look.appearance.base_colour.srgb_hex);
      $('look').add(option);
    }
    const wanted = params.get('look') || 'cotton_jersey';
    for (const option of $('look').options) if (option.text === wanted) option.selected = true;
    const apply = () => material.color.set($('look').value);  // sRGB hex; three converts to linear
    $('look').addEventListener('change', apply);
    apply();
  } catch {
    $('look').add(new Option('(looks.json missing)', '#b8442e'));
  }
}

// --- which file -------------------------------------------------------------------
async function chooseFile() {
  if (params.get('file')) {
    $('file').add(new Option(params.get('file'), params.get('file')));
    return params.get('file');
  }
  const response = await fetch('api/files');
  if (!response.ok) throw new Error('no ?file=URL given and no api/files listing here');
  const files = await response.json();
  if (!files.length) throw new Error('the server lists no .fca files');
  for (const f of files) {
    // The server's url names the file's bytes even when its name is not UTF-8.
    const url = f.url ?? 'files/' + f.name.split('/').map(encodeURIComponent).join('/');
    $('file').add(new Option(`${f.name} (${fmtBytes(f.bytes)})`, url));
  }
  $('file').addEventListener('change', () => {
    const next = new URL(location.href);
    next.searchParams.set('file', $('file').value);
    location.href = next.href;
  });
  return $('file').value;
}

// --- streaming --------------------------------------------------------------------
function setUpMesh(stream) {
  const n = stream.vertices;
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(3 * n), 3));
  geometry.setIndex(new THREE.BufferAttribute(stream.triangles(), 1));
  scene.add(new THREE.Mesh(geometry, material));
  state.geometry = geometry;
  $('scrub').max = String(stream.frames - 1);
  state.framed = false;
}

function frameCamera() {
  const geometry = state.geometry;
  geometry.computeBoundingSphere();
  const { center, radius } = geometry.boundingSphere;
  const distance = (radius / Math.sin(THREE.MathUtils.degToRad(camera.fov / 2))) * 1.1;
  camera.position.set(center.x, center.y, center.z + distance);
  camera.near = distance / 100;
  camera.far = distance * 10;
  camera.updateProjectionMatrix();
  controls.target.copy(center);
  controls.update();
  state.framed = true;
}

async function stream(url, module) {
  stats.url = url;
  stats.fetchStartMs = now();
  const response = await fetch(url);
  if (!response.ok) throw new Error(`${url}: HTTP ${response.status}`);
  const length = Number(response.headers.get('Content-Length')) || 0;
  stats.totalBytes = length || null;
  const decoder = new FcaStream(module, length);
  state.stream = decoder;
  const reader = response.body.getReader();
  for (;;) {
    const { done, value } = await reader.read();
    if (done) break;
    stats.bytes += value.length;
    decoder.feed(value);
    const status = decoder.status();
    state.status = status;
    if (status.headerReady && !state.geometry) {
      stats.headerMs = now();
      setUpMesh(decoder);
    }
    if (stats.firstFrameMs === null && status.packets >= 2) draw(0);
    if (status.headerReady && status.playableFrames === decoder.frames && stats.allPlayableMs === null) stats.allPlayableMs = now();
    if (status.complete && stats.completeMs === null) stats.completeMs = now();
  }
  stats.downloadDoneMs = now();
  if (!state.status?.complete) showError(`${url}: the file ended before its end packet (truncated); showing what arrived`);
}

// --- drawing ----------------------------------------------------------------------
let last = now();
function tick() {
  const t = now();
  const dt = (t - last) / 1000;
  last = t;
  draw(dt);
  controls.update();
  requestAnimationFrame(tick);
}

// Advances the clock by dt seconds and draws; also called as soon as the first frame is
// decodable, so that it appears without waiting for the next animation frame.
function draw(dt) {
  const s = state.stream;
  // Frames are decodable once the first data packet (the keyframes) is in, after the header.
  if (s && state.geometry && state.status && state.status.packets >= 2) {
    if (state.playing && stats.firstFrameMs !== null) state.time_s += dt;  // the clock starts at frame 0
    const index = state.playing ? Math.floor(state.time_s * s.fps) % s.frames : Number($('scrub').value);
    if (state.playing) $('scrub').value = String(index);
    // Re-decode when the frame changes or new packets may have refined it.
    if (index !== state.shown || state.status.packets !== state.shownPackets) {
      const position = state.geometry.getAttribute('position');
      s.frame(index, position.array);
      position.needsUpdate = true;
      state.geometry.computeVertexNormals();
      if (!state.framed) frameCamera();
      state.shown = index;
      state.shownPackets = state.status.packets;
      stats.framesShown++;
    }
    renderer.render(scene, camera);
    if (stats.firstFrameMs === null) {
      stats.firstFrameMs = now();
      stats.bytesAtFirstFrame = stats.bytes;
      stats.firstFrameIndex = index;
    }
    updatePanel(s, index);
  } else {
    renderer.render(scene, camera);
  }
}

function updatePanel(s, index) {
  const st = state.status;
  $('received').textContent = `received: ${fmtBytes(stats.bytes)}` + (stats.totalBytes ? ` of ${fmtBytes(stats.totalBytes)}` : '');
  $('playable').textContent = `frames final: ${st.playableFrames} of ${s.frames}` + (st.complete ? ' (complete)' : '');
  $('bound').textContent = st.maxErrorM !== null
    ? `error bound: ≤ ${(st.maxErrorM * 1000).toFixed(3)} mm on final frames` + (st.complete ? '' : '; later frames interpolated')
    : `error bound: not stated by the ${s.profile} profile` + (st.complete ? '' : '; later frames coarser');
  const ms = (x) => (x === null ? '-' : `${Math.round(x)} ms`);
  $('timing').textContent = `first frame ${ms(stats.firstFrameMs)}, all final ${ms(stats.allPlayableMs)}`;
  $('frame').textContent = `${index} / ${s.frames - 1}`;
}

async function main() {
  requestAnimationFrame(tick);
  const [module] = await Promise.all([createFoldcastDecoder(), loadLooks()]);
  const url = await chooseFile();
  await stream(url, module);
}
main().catch((e) => showError(String(e.message || e)));
