// The turntable videos `foldcast turntable` writes, in headless Chromium's <video>: the MP4
// (H.264, yuv420p, moov before mdat) and the WebM (VP9) play, and a frame read back from the
// element matches the PNG of that frame (PSNR >= 35 dB over RGB).
import { execFileSync } from 'node:child_process';
import { mkdirSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { parseArgs } from 'node:util';
import { launchChromium } from './chromium.mjs';
import { origin, serveLocally } from './local_site.mjs';

const { values: args } = parseArgs({ options: { foldcast: { type: 'string' }, chromium: { type: 'string' }, tmp: { type: 'string' } } });
rmSync(args.tmp, { recursive: true, force: true });
const files = join(args.tmp, 'files');
mkdirSync(files, { recursive: true });
const at = (name) => join(files, name);
const frames = 12, fps = 12;

// Preview frames (EGL) keep the test quick; the encoding is the same for traced ones.
writeFileSync(at('scene.toml'), `look = "denim"
[garment]
source = "drape"
grid = [32, 40]
[output]
width = 320
height = 240
[turntable]
frames = ${frames}
fps = ${fps}
`);
const turntable = (out) => execFileSync(args.foldcast, ['turntable', at('scene.toml'), '--preview', '--quiet', '-o', at(out)],
  { stdio: ['ignore', 'ignore', 'inherit'] });
turntable('spin.mp4');
turntable('spin.webm');

// ISO BMFF top-level boxes in order: +faststart puts moov before mdat.
const boxes = (buf) => {
  const names = [];
  for (let at = 0; at + 8 <= buf.length;) {
    const size = buf.readUInt32BE(at);
    names.push(buf.toString('latin1', at + 4, at + 8));
    if (size < 8) break;
    at += size;
  }
  return names;
};

const page = `<!doctype html><html><body style="margin:0">
<script>
const load = (src) => new Promise((ok, bad) => { const i = new Image(); i.onload = () => ok(i); i.onerror = bad; i.src = src; });
const pixels = (source, w, h) => {
  const c = document.createElement('canvas'); c.width = w; c.height = h;
  const g = c.getContext('2d'); g.drawImage(source, 0, 0, w, h);
  return g.getImageData(0, 0, w, h).data;
};
const once = (el, name) => new Promise((ok, bad) => { el.addEventListener(name, ok, { once: true }); el.addEventListener('error', () => bad(new Error(name + ': ' + (el.error && el.error.message))), { once: true }); });
window.check = async (src, frame, fps) => {
  const v = document.createElement('video');
  v.muted = true; v.preload = 'auto'; v.src = src;
  document.body.appendChild(v);
  await once(v, 'loadeddata');
  const result = { width: v.videoWidth, height: v.videoHeight, duration: v.duration };
  // Played: the clock advances.
  await v.play();
  await new Promise((ok) => setTimeout(ok, 400));
  result.playedTo = v.currentTime;
  v.pause();
  v.currentTime = (frame + 0.5) / fps;
  await once(v, 'seeked');
  const a = pixels(v, v.videoWidth, v.videoHeight);
  const b = pixels(await load('/files/spin_frames/frame_' + String(frame).padStart(4, '0') + '.png'), v.videoWidth, v.videoHeight);
  let se = 0, n = 0;
  for (let i = 0; i < a.length; i += 4) for (let c = 0; c < 3; c++) { const d = a[i + c] - b[i + c]; se += d * d; n++; }
  result.psnr = 10 * Math.log10(255 * 255 / (se / n));
  v.remove();
  return result;
};
window.ready = true;
</script></body></html>`;

const { browser, close } = await launchChromium(args.chromium, args.tmp);
let passed = 0, failed = 0;
const check = (ok, what) => { ok ? passed++ : failed++; console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`); };
try {
  const mp4 = readFileSync(at('spin.mp4'));
  const order = boxes(mp4);
  check(order.indexOf('moov') >= 0 && order.indexOf('moov') < order.indexOf('mdat'), `MP4 boxes ${order.join(' ')}: moov before mdat (+faststart)`);
  const tab = await browser.newPage();
  tab.on('pageerror', (e) => console.log(`page error: ${e.message}`));
  await serveLocally(tab, { '/files/': files + '/' }, { '/video.html': page });
  await tab.goto(`${origin}/video.html`);
  await tab.waitForFunction(() => window.ready, { timeout: 30000 });
  for (const [file, type] of [['spin.mp4', 'video/mp4; codecs="avc1.64001e"'], ['spin.webm', 'video/webm; codecs="vp9"']]) {
    const can = await tab.evaluate((t) => document.createElement('video').canPlayType(t), type);
    check(can !== '', `Chromium can play ${type} (${can || 'no'})`);
    for (const frame of [0, 7]) {
      const r = await tab.evaluate((src, f, rate) => window.check(src, f, rate), `/files/${file}`, frame, fps);
      check(r.width === 320 && r.height === 240 && Math.abs(r.duration - frames / fps) < 0.05 && r.playedTo > 0,
        `${file}: ${r.width}x${r.height}, ${r.duration.toFixed(3)} s, played to ${r.playedTo.toFixed(3)} s`);
      check(r.psnr >= 35, `${file} frame ${frame} vs its PNG: PSNR ${r.psnr.toFixed(2)} dB >= 35`);
    }
  }
} catch (e) {
  failed++;
  console.log(`FAIL ${e.stack || e}`);
} finally {
  await close();
}
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
