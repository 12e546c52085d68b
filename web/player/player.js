// foldcast's browser player: streams an .fca file (download.js), decodes it with the codec
// library compiled to WebAssembly (fca_stream.js) and shows every frame as soon as the bytes
// so far allow: the coarse first frame from the file's first kilobytes, then frames that
// sharpen as packets arrive (docs/player.md).
//   index.html?file=URL   any .fca URL (works from a static web server)
//   index.html            `foldcast serve`: the files it lists (api/files), first one shown
//   &look=NAME            the look (looks.json); default: the file's own (its metadata)
//   &frame=N              start paused at frame N (a permalink); &paused: start paused
import * as THREE from 'three';
import { FcaStream } from './fca_stream.js';
import { DownloadError, FileDownload, HttpDownload } from './download.js';
import { Stage } from './stage.js';
import { applyLook, createClothMaterial } from './cloth_material.js';
import { installDrop, installKeyboard, toggleFullscreen } from './controls.js';

const $ = (id) => document.getElementById(id);
const params = new URLSearchParams(location.search);
const boot = window.foldcastBoot;
const now = () => performance.now();
const fmtBytes = (n) => (n >= 1e6 ? `${(n / 1e6).toFixed(2)} MB` : `${(n / 1e3).toFixed(1)} kB`);

// What the page measured, in ms since navigation start; read by the tests and benchmarks.
const stats = {};
function resetStats(url, fetchStartMs) {
  Object.assign(stats, {
    url, fetchStartMs, totalBytes: null, bytes: 0, headerMs: null, firstFrameMs: null, bytesAtFirstFrame: null,
    firstFrameIndex: null, firstFrameCoarse: null, sharpFrameMs: null, bytesAtSharpFrame: null, allPlayableMs: null,
    completeMs: null, downloadDoneMs: null, error: null, errorKind: null, framesShown: 0, requests: 0, rangeRequests: 0,
    look: null, metadata: null,
  });
}

const state = {
  job: null, module: null, playing: params.get('paused') === null && params.get('frame') === null, speed: 1, loop: true,
  time_s: 0, shown: -1, shownPackets: -1, geometry: null, mesh: null, looks: null, lookChosen: params.get('look'),
  startFrame: params.get('frame') !== null ? Math.max(0, Math.floor(Number(params.get('frame')) || 0)) : null,
};

const stage = new Stage($('view'), () => requestDraw());
const material = createClothMaterial();

window.foldcastPlayer = {
  stats,
  pause() { setPlaying(false); },
  play() { setPlaying(true); },
  seek(t) { seek(t); },
  renders: () => stage.renders,
  state: () => ({ playing: state.playing, speed: state.speed, loop: state.loop, frame: state.shown,
    look: $('look').selectedOptions[0]?.text ?? null, permalink: $('permalink').href,
    camera: stage.camera.position.toArray(), fullscreen: Boolean(document.fullscreenElement) }),
  // The frame on screen: index, packets it was decoded from, and its float32 xyz bytes (base64).
  shownFrame() {
    const pos = state.geometry?.getAttribute('position');
    if (!pos) return null;
    const bytes = new Uint8Array(pos.array.buffer, pos.array.byteOffset, pos.array.byteLength);
    let text = '';
    for (let i = 0; i < bytes.length; i += 0x8000) text += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
    return { index: state.shown, packets: state.shownPackets, complete: state.job?.status?.complete ?? false,
      coarse: state.job?.status?.previewOnly ?? false, base64: btoa(text) };
  },
};

// --- drawing on demand ------------------------------------------------------------
let drawPending = false, lastTick = null;
function requestDraw() {
  if (drawPending) return;
  drawPending = true;
  requestAnimationFrame(tick);
}

function tick(t) {
  drawPending = false;
  const s = state.job?.decoder, st = state.job?.status;
  if (state.playing && s && st?.frameReady && stats.firstFrameMs !== null) {
    if (lastTick !== null) state.time_s += ((t - lastTick) / 1000) * state.speed;
    lastTick = t;
    let index = Math.floor(state.time_s * s.fps);
    if (index >= s.frames && !state.loop) {
      index = s.frames - 1;
      setPlaying(false);
    }
    $('scrub').value = String(index % s.frames);
  } else {
    lastTick = null;
  }
  draw();
  if (state.playing) requestDraw();
}

function draw() {
  const job = state.job, s = job?.decoder, st = job?.status;
  if (s && state.geometry && st?.frameReady) {
    const index = Number($('scrub').value);
    // Decoded again when the frame changes or new packets may have refined it.
    if (index !== state.shown || st.packets !== state.shownPackets) {
      const position = state.geometry.getAttribute('position');
      s.frame(index, position.array);
      position.needsUpdate = true;
      state.geometry.computeVertexNormals();
      if (!state.framed) {
        stage.frame(state.geometry);
        state.framed = true;
      }
      state.shown = index;
      state.shownPackets = st.packets;
      stats.framesShown++;
    }
    if (stats.firstFrameMs === null) {
      Object.assign(stats, { firstFrameMs: now(), bytesAtFirstFrame: stats.bytes, firstFrameIndex: index, firstFrameCoarse: st.previewOnly });
      updatePanel();
    }
    if (stats.sharpFrameMs === null && !st.previewOnly) Object.assign(stats, { sharpFrameMs: now(), bytesAtSharpFrame: stats.bytes });
    $('frame').textContent = `${index} / ${s.frames - 1} · ${+s.fps.toFixed(2)} fps`;
  }
  stage.render();
}

// --- playback controls --------------------------------------------------------------
function setPlaying(on) {
  const s = state.job?.decoder;
  if (on && s?.frames && !state.loop && Number($('scrub').value) >= s.frames - 1) $('scrub').value = '0';
  state.playing = on;
  if (on) state.time_s = Number($('scrub').value) / (s?.fps || 30);
  $('play').textContent = on ? 'pause' : 'play';
  if (!on) updateUrl();
  requestDraw();
}

function seek(t) {
  const frames = state.job?.decoder?.frames;
  const index = frames ? Math.min(Math.max(0, Math.round(t)), frames - 1) : Math.max(0, Math.round(t));
  $('scrub').value = String(index);
  state.playing = false;
  $('play').textContent = 'play';
  updateUrl(index);
  requestDraw();
}

$('play').addEventListener('click', () => setPlaying(!state.playing));
$('scrub').addEventListener('input', () => seek(Number($('scrub').value)));
$('speed').addEventListener('change', () => { state.speed = Number($('speed').value); });
$('loop').addEventListener('change', () => { state.loop = $('loop').checked; });
$('reset').addEventListener('click', () => stage.reset());
$('fullscreen').addEventListener('click', toggleFullscreen);
installKeyboard($('scrub'), {
  togglePlay: () => setPlaying(!state.playing),
  step: (n) => seek(Number($('scrub').value) + n),
  first: () => seek(0),
  last: () => seek((state.job?.decoder?.frames ?? 1) - 1),
  resetView: () => stage.reset(),
  toggleLoop: () => { $('loop').checked = !$('loop').checked; state.loop = $('loop').checked; },
});

// --- the permalink: file, look and (when paused) frame ----------------------------------
function updateUrl(frame = Number($('scrub').value)) {
  const url = new URL(location.href);
  const job = state.job;
  if (job?.download instanceof HttpDownload) url.searchParams.set('file', job.download.url);
  else url.searchParams.delete('file');  // a local file has no address
  if (state.lookChosen) url.searchParams.set('look', state.lookChosen);
  else url.searchParams.delete('look');
  url.searchParams.delete('paused');
  if (state.playing) url.searchParams.delete('frame');
  else url.searchParams.set('frame', String(frame));
  history.replaceState(null, '', url);
  $('permalink').href = url.href;
}

// --- looks: the file's own unless one was chosen -----------------------------------------
function applySelectedLook() {
  const look = state.looks?.find((l) => l.name === $('look').value);
  if (!look) return;
  stats.look = applyLook(material, look, stage.renderer.capabilities.getMaxAnisotropy());
  requestDraw();
}

function selectLook() {
  if (!state.looks) return;
  const wanted = state.lookChosen || state.job?.decoder?.metadata?.look || 'cotton_jersey';
  const name = state.looks.some((l) => l.name === wanted) ? wanted : 'cotton_jersey';
  if ($('look').value !== name || !stats.look) {
    $('look').value = name;
    applySelectedLook();
  }
}

$('look').addEventListener('change', () => {
  state.lookChosen = $('look').value;
  applySelectedLook();
  updateUrl();
});

async function loadLooks() {
  try {
    state.looks = (await boot.looks).looks;
    for (const look of state.looks) $('look').add(new Option(look.name, look.name));
    selectLook();
  } catch {
    $('look').add(new Option('(looks.json missing)', ''));
  }
}

// --- the file list (foldcast serve's api/files), kept and switchable ------------------------
async function loadListing() {
  try {
    const files = await boot.listing;
    for (const f of files) {
      // The server's url names the file's bytes even when its name is not UTF-8.
      const url = f.url ?? 'files/' + f.name.split('/').map(encodeURIComponent).join('/');
      const option = new Option(`${f.name} (${fmtBytes(f.bytes)})`, url);
      option.title = f.name;
      $('file').add(option);
    }
    return files;
  } catch {
    return null;
  }
}

$('file').addEventListener('change', () => {
  if ($('file').value) open(new HttpDownload($('file').value));
});

// --- drag-and-drop and the file picker: a local .fca ------------------------------------
function openLocal(file) {
  if (!file) return;
  if (!/\.fca$/i.test(file.name)) {
    showError('input', `${file.name} is not an .fca file (its name does not end in .fca)`);
    return;
  }
  const option = new Option(`${file.name} (local, ${fmtBytes(file.size)})`, '');
  $('file').add(option);
  option.selected = true;
  open(new FileDownload(file));
}
$('open').addEventListener('change', () => openLocal($('open').files[0]));
installDrop($('drop-hint'), openLocal);

// --- errors ---------------------------------------------------------------------------
function showError(kind, message, retry = false) {
  stats.error = message;
  stats.errorKind = kind;
  $('error').hidden = false;
  $('error-text').textContent = message;
  $('retry').hidden = !retry;
}
function clearError() {
  stats.error = stats.errorKind = null;
  $('error').hidden = true;
  $('retry').hidden = true;
}
$('retry').addEventListener('click', () => {
  const job = state.job;
  if (!job || job.running) return;
  clearError();
  run(job);
});

// --- streaming ------------------------------------------------------------------------
function closeJob() {
  const job = state.job;
  if (!job) return;
  job.closed = true;
  job.download.abort();
  job.decoder?.dispose();
  if (state.mesh) {
    stage.scene.remove(state.mesh);
    state.geometry.dispose();
  }
  Object.assign(state, { job: null, mesh: null, geometry: null, shown: -1, shownPackets: -1, framed: false, time_s: 0 });
}

function open(download) {
  closeJob();
  clearError();
  resetStats(download.url ?? download.label, download.startMs);
  const job = { download, decoder: null, queue: [], status: null, corrupt: null, ended: false, running: false, closed: false };
  state.job = job;
  $('scrub').value = '0';
  updatePanel();
  if (download instanceof HttpDownload) updateUrl(state.startFrame ?? 0);
  run(job);
}

async function run(job) {
  job.running = true;
  try {
    await job.download.run((chunk) => {
      if (job.closed || job.corrupt) return;
      stats.bytes = job.download.received;
      stats.totalBytes = job.download.total;
      job.queue.push(chunk);
      pump(job);
    });
    job.ended = true;
    stats.downloadDoneMs = now();
  } catch (e) {
    if (job.closed || e?.name === 'AbortError') return;
    if (e instanceof DownloadError) showError(e.kind, e.message, e.kind === 'network');
    else showError('network', `${job.download.label}: ${e.message || e}`, true);
  } finally {
    job.running = false;
    Object.assign(stats, { requests: job.download.requests, rangeRequests: job.download.rangeRequests });
  }
  pump(job);
}

// Feeds what has arrived to the decoder once WebAssembly is ready (the download starts
// before it), and says what the file is once the download has ended.
function pump(job) {
  if (job.closed) return;
  if (!job.decoder) {
    if (!state.module || (job.download.total === null && !job.ended)) return;
    job.decoder = new FcaStream(state.module, job.download.total || 0);
  }
  while (job.queue.length && !job.corrupt) {
    const chunk = job.queue.shift();
    try {
      job.decoder.feed(chunk);
    } catch (e) {
      // The decoder keeps every packet it accepted before the bad one: those frames stay.
      job.corrupt = e.message;
      job.queue.length = 0;
      job.download.abort();
    }
  }
  afterFeed(job);
  if (job.corrupt && !stats.error) {
    const kept = job.status?.frameReady ? 'showing the frames that arrived before it' : 'no frame arrived before it';
    showError('corrupt', `${job.download.label} is corrupt: ${job.corrupt}; ${kept}`);
  } else if (job.ended && !job.queue.length && !job.corrupt && !stats.error) {
    explainEnd(job);
  }
}

function afterFeed(job) {
  const s = job.decoder, st = s.status();
  job.status = st;
  if (st.headerReady && !state.geometry) {
    stats.headerMs = now();
    stats.metadata = s.metadata;
    setUpMesh(s);
    selectLook();
  }
  if (st.headerReady && st.playableFrames === s.frames && stats.allPlayableMs === null) stats.allPlayableMs = now();
  if (st.complete && stats.completeMs === null) stats.completeMs = now();
  updatePanel();
  // Redraw only when what is on screen may change: a first or refined frame.
  if (st.frameReady && st.packets !== state.shownPackets) requestDraw();
}

function explainEnd(job) {
  const st = job.status, label = job.download.label, n = stats.bytes;
  if (n === 0) showError('empty', `${label} is empty (0 bytes): nothing to play`);
  else if (!st?.headerReady) showError('truncated', `${label} is truncated inside its header (${n} bytes): nothing to play`);
  else if (!st.frameReady) {
    showError('truncated', `${label} is truncated: it ends after ${n} bytes, before its first frame` +
      (st.firstFrameBytes ? ` (which needs ${st.firstFrameBytes} bytes)` : '') + ': nothing to show');
  } else if (!st.complete) {
    showError('truncated', `${label} is truncated: it ends after ${n} bytes; ` +
      (st.playableFrames ? `frames 0-${st.playableFrames - 1} are final, later ones interpolated`
        : 'no frame is final, all are interpolated' + (st.previewOnly ? ' (a coarse preview of frame 0)' : '')));
  }
}

function setUpMesh(s) {
  const n = s.vertices;
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(3 * n), 3));
  geometry.setIndex(new THREE.BufferAttribute(s.triangles(), 1));
  const uvs = s.uvs();
  geometry.setAttribute('uv', new THREE.BufferAttribute(uvs ?? new Float32Array(2 * n), 2));
  state.needsPlanarUvs = !uvs;
  state.geometry = geometry;
  state.mesh = new THREE.Mesh(geometry, material);
  stage.scene.add(state.mesh);
  $('scrub').max = String(s.frames - 1);
  if (state.startFrame !== null) {
    $('scrub').value = String(Math.min(state.startFrame, s.frames - 1));
    state.startFrame = null;
  }
  state.framed = false;
}

function updatePanel() {
  const job = state.job, st = job?.status, s = job?.decoder;
  const total = stats.totalBytes;
  $('progress').max = total || 1;
  $('progress').value = total ? stats.bytes : 0;
  $('received').textContent = stats.bytes || total
    ? `received: ${fmtBytes(stats.bytes)}` + (total ? ` of ${fmtBytes(total)} (${Math.floor((100 * stats.bytes) / total)} %)` : '')
    : 'received: waiting for the first bytes';
  if (!st?.headerReady) return;
  $('playable').textContent = `frames final: ${st.playableFrames} of ${s.frames}` + (st.complete ? ' (complete)'
    : st.previewOnly ? '; showing a coarse preview of frame 0' : '');
  $('bound').textContent = st.maxErrorM !== null
    ? `error bound: ≤ ${(st.maxErrorM * 1000).toFixed(3)} mm on final frames` + (st.complete ? '' : '; later frames interpolated')
    : `error bound: not stated by the ${s.profile} profile` + (st.complete ? '' : '; later frames coarser');
  const ms = (x) => (x === null ? '-' : `${Math.round(x)} ms`);
  $('timing').textContent = `first frame ${ms(stats.firstFrameMs)}, all final ${ms(stats.allPlayableMs)}`;
  // The scrub bar: dark up to the last final frame, light where frames are interpolated.
  const final = (100 * st.playableFrames) / s.frames, ready = st.frameReady && !st.previewOnly ? 100 : final;
  $('timeline').style.background = `linear-gradient(to right, #3d6fb6 0 ${final}%, #a9c0e0 ${final}% ${ready}%, #c9ccd1 ${ready}% 100%)`;
  $('timeline').dataset.final = String(st.playableFrames);
  $('timeline').dataset.interpolated = String(st.frameReady && !st.previewOnly ? s.frames - st.playableFrames : 0);
  if (state.needsPlanarUvs && st.frameReady) planarUvs(s);
}

// A file without UVs: the weave laid flat over frame 0's x and y (metres), as drape's would be.
function planarUvs(s) {
  const frame = s.frame(0), uv = state.geometry.getAttribute('uv');
  for (let v = 0; v < s.vertices; ++v) {
    uv.array[2 * v] = frame[3 * v];
    uv.array[2 * v + 1] = frame[3 * v + 1];
  }
  uv.needsUpdate = true;
  state.needsPlanarUvs = false;
}

async function main() {
  $('play').textContent = state.playing ? 'pause' : 'play';
  $('permalink').href = location.href;
  boot.decoder.then((module) => {
    state.module = module;
    if (state.job) pump(state.job);
  }, (e) => showError('decoder', `the WebAssembly decoder did not start: ${e.message || e}`));
  loadLooks();
  if (boot.early) {
    open(new HttpDownload(boot.early.url, boot.early));
    const files = await loadListing();
    if (files) {
      // Show the playing file in the list: its listed entry, or its address.
      const listed = [...$('file').options].find((o) => o.value === boot.early.url);
      if (listed) {
        listed.selected = true;
      } else {
        $('file').add(new Option(boot.early.url, boot.early.url), 0);
        $('file').selectedIndex = 0;
      }
    } else {
      $('file').add(new Option(boot.early.url, boot.early.url));
    }
    return;
  }
  const files = await loadListing();
  if (!files) throw new Error('no ?file=URL given and no api/files listing here');
  if (!files.length) throw new Error('the server lists no .fca files');
  open(new HttpDownload($('file').value));
}
main().catch((e) => showError('input', String(e.message || e)));
requestDraw();
