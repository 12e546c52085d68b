// The player in headless Chromium (Debian's, driven by puppeteer-core), as a viewer uses it,
// loading drape animations from `foldcast serve`:
//  * streaming (throttled): the download starts before the decoder is ready, a coarse frame 0
//    is on screen after a few percent of the bytes and sharpens, the progress bar and the
//    scrub bar's final/interpolated ranges follow the bytes, the last frame on screen is bit
//    for bit `foldcast decode`'s; the file's look (its metadata) is the one shown, woven;
//  * controls: file list kept and switchable, keyboard, speed, loop, reset view, fullscreen,
//    permalink (file, look, frame), no redraw while paused, drag-and-drop of a local .fca,
//    a layout that leaves the garment uncovered on a desktop and on a phone;
//  * errors: empty, truncated and corrupt files told apart, good frames before a corrupt
//    packet kept on a fast link, an interrupted download resumed with a Range request.
// --grid/--frames/--kbps/--look/--runs make it the first-frame measurement of
// docs/benchmarks.md (`--measure` skips everything else; `--look none`: drape's default cloth).
import { execFileSync } from 'node:child_process';
import { copyFileSync, mkdirSync, readFileSync, rmSync, statSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { parseArgs } from 'node:util';
import { launchChromium } from './chromium.mjs';
import { startServe } from './serve_process.mjs';

const { values: args } = parseArgs({
  options: {
    foldcast: { type: 'string' }, chromium: { type: 'string' }, tmp: { type: 'string' },
    grid: { type: 'string', default: '48x48' }, frames: { type: 'string', default: '96' }, kbps: { type: 'string' },
    look: { type: 'string', default: 'denim' }, measure: { type: 'boolean', default: false }, runs: { type: 'string', default: '1' },
  },
});
rmSync(args.tmp, { recursive: true, force: true });
const files = join(args.tmp, 'files');
mkdirSync(files, { recursive: true });
const foldcast = (list) => execFileSync(args.foldcast, list, { stdio: 'ignore' });

const fca = join(files, 'drape.fca');
foldcast(['drape', '--grid', args.grid, '--frames', args.frames, '--sway-m', '0.02', ...(args.look === 'none' ? [] : ['--look', args.look]), '-o', fca]);
const bytes = readFileSync(fca);
const size = bytes.length;
const kbps = Number(args.kbps) || Math.max(8, Math.round((size * 8) / 1000 / 4));  // default: about 4 s
// The packets' ends: header, preview, data packet 0.
const ends = [];
for (let at = 8; ends.length < 3; ) ends.push((at += 9 + bytes.readUInt32LE(at)));

let passed = 0, failed = 0;
const check = (ok, what) => {
  ok ? passed++ : failed++;
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
};
const servers = [];
const serve = async (dir, extra = [], port = 0) => {
  const s = await startServe(args.foldcast, dir, extra, port);
  let stopped = null;
  const server = { port: s.port, stop: () => (stopped ??= s.stop()) };  // once: a second SIGINT would wait forever
  servers.push(server);
  return server;
};
const throttled = await serve(files, ['--throttle-kbps', String(kbps)]);
const { browser, close } = await launchChromium(args.chromium, args.tmp);

async function newPage(viewport) {
  const page = await browser.newPage();
  if (viewport) await page.setViewport(viewport);
  page.on('console', (m) => { if (!m.text().includes('GL Driver Message')) console.log(`page: ${m.text()}`); });
  page.on('pageerror', (e) => console.log(`page error: ${e.message}`));
  return page;
}
const stats = (page) => page.evaluate(() => window.foldcastPlayer.stats);
const playerState = (page) => page.evaluate(() => window.foldcastPlayer.state());
const waitFor = (page, fn, arg, timeout = 60000) => page.waitForFunction(fn, { timeout, polling: 50 }, arg);
const sleep = (ms) => new Promise((done) => setTimeout(done, ms));
const waitEnded = (page) => waitFor(page, () => window.foldcastPlayer?.stats.downloadDoneMs !== null || window.foldcastPlayer?.stats.error, null, 180000);

// The first frame at a given link speed: the measurement for docs/benchmarks.md.
async function streaming() {
  const page = await newPage();
  await page.goto(`http://127.0.0.1:${throttled.port}/?file=files/drape.fca`);
  // Samples of what the page shows while the bytes arrive.
  const samples = [];
  let ended = false;
  const sampling = (async () => {
    while (!ended) {
      samples.push(await page.evaluate(() => ({ bytes: window.foldcastPlayer?.stats.bytes ?? 0,
        progress: document.getElementById('progress').value, final: Number(document.getElementById('timeline').dataset.final ?? 0),
        interpolated: Number(document.getElementById('timeline').dataset.interpolated ?? 0) })).catch(() => ({})));
      await sleep(150);
    }
  })();
  await waitEnded(page);
  ended = true;
  await sampling;
  const s = await stats(page);
  const at = (x) => Math.round(x);
  console.log(`${args.grid} x ${args.frames}, ${size} bytes at ${kbps} kbit/s: first frame ${at(s.firstFrameMs)} ms after navigation ` +
    `(${s.bytesAtFirstFrame} bytes, ${(100 * s.bytesAtFirstFrame / size).toFixed(1)} %${s.firstFrameCoarse ? ', coarse' : ''}), ` +
    `sharp ${at(s.sharpFrameMs)} ms (${s.bytesAtSharpFrame} bytes), all final ${at(s.allPlayableMs)} ms, complete ${at(s.completeMs)} ms; ` +
    `header ${ends[0]} bytes, preview ends at ${ends[1]}, data packet 0 at ${ends[2]}`);
  console.log(`MEASURE ${JSON.stringify({ grid: args.grid, frames: Number(args.frames), bytes: size, kbps, first_frame_ms: at(s.firstFrameMs),
    bytes_at_first_frame: s.bytesAtFirstFrame, sharp_frame_ms: at(s.sharpFrameMs), all_final_ms: at(s.allPlayableMs), complete_ms: at(s.completeMs) })}`);
  check(s.error === null, `no error (${s.error})`);
  check(s.totalBytes === size && s.bytes === size, 'every byte arrived');
  const timing = await page.evaluate(() => {
    const entries = performance.getEntriesByType('resource');
    const find = (end) => entries.find((e) => e.name.endsWith(end));
    return { fcaStart: find('drape.fca')?.startTime, wasmEnd: find('.wasm')?.responseEnd, playerStart: find('player.js')?.startTime };
  });
  check(timing.fcaStart !== undefined && timing.fcaStart < timing.wasmEnd,
    `the download started (${Math.round(timing.fcaStart)} ms) before the decoder had loaded (${Math.round(timing.wasmEnd)} ms)`);
  // Coarse when drawn before data packet 0 had arrived (on a small file the decoder's
  // start-up may take longer than data packet 0: the preview-only file below checks it then).
  check(s.firstFrameIndex === 0 && s.firstFrameCoarse === (s.bytesAtFirstFrame < ends[2]) && s.bytesAtFirstFrame < size / 2,
    `the first frame shown is frame 0 (${s.firstFrameCoarse ? 'coarse' : 'sharp'}), after ${s.bytesAtFirstFrame} of ${size} bytes ` +
    `(preview ends at ${ends[1]}, data packet 0 at ${ends[2]})`);
  check(s.sharpFrameMs >= s.firstFrameMs && s.sharpFrameMs < s.downloadDoneMs, 'it is sharp before the download finished');
  check(s.completeMs !== null && s.allPlayableMs !== null, 'the stream completed: every frame final');
  const during = samples.filter((x) => x.bytes > 0 && x.bytes < size);
  check(during.some((x) => x.progress > 0 && x.progress < size && x.final > 0 && x.final < Number(args.frames) && x.interpolated > 0),
    `the progress bar and the scrub bar's final and interpolated ranges grew with the bytes (${during.length} samples)`);
  return page;
}

async function lookAndFrames(page) {
  const st = await playerState(page);
  const s = await stats(page);
  check(st.look === 'denim' && s.metadata?.look === 'denim', `the file's look (metadata: ${s.metadata?.look}) is chosen: ${st.look}`);
  check(s.look?.textured && s.look.weave === 'twill' && s.look.sheenColour, `woven, with sheen: ${JSON.stringify(s.look)}`);
  const pc2 = join(args.tmp, 'native.pc2');
  foldcast(['decode', fca, '-o', pc2]);
  const native = readFileSync(pc2);
  const vertices = native.readInt32LE(16), frames = native.readInt32LE(28);
  const last = frames - 1;
  await page.evaluate((t) => window.foldcastPlayer.seek(t), last);
  await waitFor(page, (t) => window.foldcastPlayer.shownFrame()?.index === t, last);
  const shown = await page.evaluate(() => window.foldcastPlayer.shownFrame());
  const expected = native.subarray(32 + last * vertices * 12, 32 + (last + 1) * vertices * 12);
  check(shown.complete && Buffer.from(shown.base64, 'base64').equals(expected), `frame ${last} on screen equals the native decode (${vertices} vertices)`);
  await page.screenshot({ path: join(args.tmp, 'player.png') });
  console.log(`screenshot: ${join(args.tmp, 'player.png')}`);
}

async function controls(page, fast) {
  const frames = Number(args.frames);
  await page.evaluate(() => window.foldcastPlayer.seek(0));
  await page.focus('#view');
  const frame = async () => (await playerState(page)).frame;
  await page.keyboard.press('ArrowRight');
  await page.keyboard.down('Shift');
  await page.keyboard.press('ArrowRight');
  await page.keyboard.up('Shift');
  await waitFor(page, () => window.foldcastPlayer.state().frame === 11);
  check(await frame() === 11, 'arrow keys step 1 and (Shift) 10 frames');
  await page.keyboard.press('End');
  await waitFor(page, (f) => window.foldcastPlayer.state().frame === f - 1, frames);
  await page.keyboard.press('Home');
  await waitFor(page, () => window.foldcastPlayer.state().frame === 0);
  check(true, 'End and Home go to the last and first frame');
  await page.keyboard.press(' ');
  check((await playerState(page)).playing && (await page.$eval('#play', (b) => b.textContent)) === 'pause', 'Space plays (the button says pause)');
  await page.select('#speed', '2');
  await page.keyboard.press('l');
  const st = await playerState(page);
  check(st.speed === 2 && st.loop === false, `speed 2x and L turns loop off (${st.speed}, ${st.loop})`);
  await sleep(1000);
  check((await frame()) > 0, `it plays (frame ${await frame()} after 1 s at 2x)`);
  if ((await playerState(page)).playing) await page.keyboard.press(' ');  // (loop off: it may have stopped at the end)
  check(!(await playerState(page)).playing && (await page.$eval('#play', (b) => b.textContent)) === 'play', 'paused (the button says play)');
  await sleep(200);
  const before = await page.evaluate(() => window.foldcastPlayer.renders());
  await sleep(1000);
  const after = await page.evaluate(() => window.foldcastPlayer.renders());
  check(after - before <= 1, `no redraw while paused (${after - before} in 1 s)`);
  // Orbit with the mouse, then reset the view.
  const home = (await playerState(page)).camera;
  const box = await (await page.$('#view')).boundingBox();
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await page.mouse.down();
  await page.mouse.move(box.x + box.width / 2 + 150, box.y + box.height / 2 + 40, { steps: 8 });
  await page.mouse.up();
  const moved = (await playerState(page)).camera;
  await page.click('#reset');
  const reset = (await playerState(page)).camera;
  const same = (a, b) => a.every((x, i) => Math.abs(x - b[i]) < 1e-6);
  check(!same(home, moved) && same(home, reset), 'orbiting moves the camera, reset view brings it back');
  // After a click on a button, Space still plays and pauses (it does not press the button again).
  await page.keyboard.press(' ');
  const playing = (await playerState(page)).playing;
  await page.keyboard.press(' ');
  check(playing && !(await playerState(page)).playing && same(home, (await playerState(page)).camera),
    'after clicking a button, Space plays and pauses');
  await page.click('#fullscreen');
  await sleep(300);
  const full = (await playerState(page)).fullscreen;
  console.log(`${full ? 'ok  ' : 'note'} fullscreen: document.fullscreenElement ${full ? 'set' : 'not set (headless Chromium may refuse)'}`);
  if (full) await page.click('#fullscreen');
  // The permalink keeps file, look and frame.
  await page.select('#look', 'satin');
  await page.evaluate(() => window.foldcastPlayer.seek(17));
  const link = (await playerState(page)).permalink;
  const url = new URL(link);
  check(url.searchParams.get('file') === 'files/drape.fca' && url.searchParams.get('look') === 'satin' && url.searchParams.get('frame') === '17',
    `permalink ${url.search}`);
  const again = await newPage();
  url.port = String(fast.port);  // the same page from the unthrottled server
  await again.goto(url.href);
  await waitFor(again, () => window.foldcastPlayer?.stats.completeMs !== null && window.foldcastPlayer.state().frame === 17, null, 120000);
  const st2 = await playerState(again);
  check(st2.look === 'satin' && !st2.playing && (await again.$eval('#play', (b) => b.textContent)) === 'play',
    `the permalink opens paused at frame 17 in satin (button says ${await again.$eval('#play', (b) => b.textContent)})`);
  await again.close();
}

async function listAndLayout(page, viewport, name) {
  await page.setViewport(viewport);
  await sleep(300);
  const r = await page.evaluate(() => {
    const rect = (id) => document.getElementById(id).getBoundingClientRect().toJSON();
    return { view: rect('view'), panel: rect('panel'), controls: rect('controls'), scrollWidth: document.documentElement.scrollWidth,
      width: innerWidth, options: [...document.getElementById('file').options].map((o) => o.value),
      selected: document.getElementById('file').value };
  });
  const overlap = (a, b) => a.left < b.right - 0.5 && b.left < a.right - 0.5 && a.top < b.bottom - 0.5 && b.top < a.bottom - 0.5;
  check(!overlap(r.view, r.panel) && !overlap(r.view, r.controls) && r.view.width > 100 && r.view.height > 100,
    `${name}: the panel and the controls leave the garment's ${Math.round(r.view.width)}x${Math.round(r.view.height)} px uncovered`);
  check(r.scrollWidth <= r.width, `${name}: nothing wider than the window (${r.scrollWidth} <= ${r.width})`);
  return r;
}

async function fileList(page) {
  const r = await listAndLayout(page, { width: 960, height: 640 }, 'desktop');
  check(r.options.length >= 5 && r.selected === 'files/drape.fca', `the file list is kept (${r.options.length} files, drape.fca selected)`);
  await listAndLayout(page, { width: 390, height: 844, isMobile: true, hasTouch: true }, 'phone');
  await page.screenshot({ path: join(args.tmp, 'player-phone.png') });
  await page.setViewport({ width: 960, height: 640 });
  const long = r.options.find((o) => o.includes('long'));
  await page.select('#file', long);
  await waitFor(page, () => window.foldcastPlayer.stats.completeMs !== null || window.foldcastPlayer.stats.error, null, 120000);
  const s = await stats(page);
  check(s.url === long && s.error === null && new URL(page.url()).searchParams.get('file') === long,
    `switching files in the list plays the other (${decodeURIComponent(long)}) and updates the address`);
}

async function dragAndDrop(page) {
  await page.evaluate(async () => {
    const blob = await (await fetch('files/small.fca')).blob();
    const transfer = new DataTransfer();
    transfer.items.add(new File([blob], 'dropped.fca'));
    document.dispatchEvent(new DragEvent('dragenter', { dataTransfer: transfer, cancelable: true }));
    document.dispatchEvent(new DragEvent('drop', { dataTransfer: transfer, cancelable: true }));
  });
  await waitFor(page, () => window.foldcastPlayer.stats.url === 'dropped.fca' && (window.foldcastPlayer.stats.completeMs !== null || window.foldcastPlayer.stats.error));
  const s = await stats(page);
  check(s.error === null && s.completeMs !== null && (await page.$eval('#drop-hint', (d) => d.hidden)),
    `a dropped local .fca plays (${s.bytes} bytes, ${s.error})`);
}

async function errors(page) {
  const cases = [
    ['empty.fca', 'empty', /is empty \(0 bytes\)/],
    ['header-only.fca', 'truncated', /before its first frame \(which needs \d+ bytes\): nothing to show/],
    ['preview-only.fca', 'truncated', /no frame is final, all are interpolated \(a coarse preview of frame 0\)/],
    ['half.fca', 'truncated', /truncated: it ends after \d+ bytes; frames 0-\d+ are final/],
    ['corrupt.fca', 'corrupt', /is corrupt: .*CRC mismatch.*; showing the frames that arrived before it/],
  ];
  // Switching files in the page's list (a page load costs seconds on SwiftShader).
  for (const [file, kind, text] of cases) {
    const keeps = ['corrupt.fca', 'half.fca', 'preview-only.fca'].includes(file);
    await page.select('#file', `files/${file}`);
    // The error can be known before the frames that arrived are drawn (drawing is slower under
    // load): where frames are to be kept, wait for them too, up to the timeout.
    await waitFor(page, ({ url, keeps }) => {
      const p = window.foldcastPlayer;
      return p.stats.url === url && p.stats.error && (!keeps || (p.stats.firstFrameMs !== null && p.shownFrame()?.index >= 0));
    }, { url: `files/${file}`, keeps }).catch(() => {});
    const s = await stats(page);
    const shown = await page.evaluate(() => window.foldcastPlayer.shownFrame());
    const drawn = s.firstFrameMs !== null && shown?.index >= 0;
    const framesKept = keeps ? drawn && shown.coarse === (file === 'preview-only.fca') : !drawn;
    check(s.errorKind === kind && text.test(s.error) && framesKept && (await page.$eval('#error', (e) => !e.hidden)),
      `${file}: "${s.error}"${drawn ? `, frames on screen${shown.coarse ? ' (the coarse preview)' : ''}` : ', nothing drawn'}` +
      (kind === 'corrupt' ? ' (good frames kept on an unthrottled link)' : ''));
  }
}

async function resume() {
  // Its own server, stopped mid-download and started again on the same port.
  const dir = join(args.tmp, 'resume');
  mkdirSync(dir, { recursive: true });
  copyFileSync(fca, join(dir, 'drape.fca'));
  // Slow enough (about 8 s for the file) that it is stopped well before the end on a loaded machine.
  const first = await serve(dir, ['--throttle-kbps', String(Math.max(8, Math.round(kbps / 2)))]);
  const page = await newPage();
  await page.goto(`http://127.0.0.1:${first.port}/?file=files/drape.fca`);
  await waitFor(page, (n) => window.foldcastPlayer?.stats.bytes > n, Math.floor(size / 4));
  await first.stop();
  await waitFor(page, () => window.foldcastPlayer.stats.errorKind !== null || window.foldcastPlayer.stats.downloadDoneMs !== null, null, 120000);
  const s1 = await stats(page);
  check(s1.errorKind === 'network' && await page.$eval('#retry', (b) => !b.hidden),
    `the server stopped mid-download: "${s1.error}" after ${s1.bytes} of ${size} bytes, with a retry button`);
  await serve(dir, ['--throttle-kbps', String(kbps * 4)], first.port);
  await page.click('#retry');
  await waitFor(page, () => window.foldcastPlayer.stats.completeMs !== null || window.foldcastPlayer.stats.error, null, 120000);
  const s2 = await stats(page);
  check(s2.error === null && s2.bytes === size && s2.rangeRequests === 1,
    `retry resumed with a Range request from byte ${s1.bytes} and completed (${s2.requests} requests, ${s2.rangeRequests} with Range)`);
  await page.evaluate((t) => window.foldcastPlayer.seek(t), Number(args.frames) - 1);
  const native = readFileSync(join(args.tmp, 'native.pc2'));
  const vertices = native.readInt32LE(16), last = Number(args.frames) - 1;
  await waitFor(page, (t) => window.foldcastPlayer.shownFrame()?.index === t, last);
  const shown = await page.evaluate(() => window.foldcastPlayer.shownFrame());
  check(Buffer.from(shown.base64, 'base64').equals(native.subarray(32 + last * vertices * 12, 32 + (last + 1) * vertices * 12)),
    'the resumed file decodes to the native frames');
  await page.close();
}

async function cascadeProfile() {
  // The same animation encoded with profile cascade, streamed over the throttled link from its
  // own server: it plays to the end and its last frame is the native decode's.
  const dir = join(args.tmp, 'cascade');
  mkdirSync(dir, { recursive: true });
  const source = join(dir, 'source.pc2'), file = join(dir, 'cascade.fca'), decoded = join(dir, 'native.pc2');
  foldcast(['decode', fca, '-o', source]);
  foldcast(['encode', source, '-o', file, '--profile', 'cascade']);
  foldcast(['decode', file, '-o', decoded]);
  const server = await serve(dir, ['--throttle-kbps', String(kbps)]);
  const page = await newPage();
  await page.goto(`http://127.0.0.1:${server.port}/?file=files/cascade.fca`);
  await waitFor(page, () => window.foldcastPlayer?.stats.completeMs != null || window.foldcastPlayer?.stats.error, null, 120000);
  const s = await stats(page);
  check(s.error === null && s.bytes === readFileSync(file).length, `a cascade file streams to the end (${s.bytes} bytes)`);
  const native = readFileSync(decoded);
  const vertices = native.readInt32LE(16), last = native.readInt32LE(28) - 1;
  await page.evaluate((t) => window.foldcastPlayer.seek(t), last);
  await waitFor(page, (t) => window.foldcastPlayer.shownFrame()?.index === t, last);
  const shown = await page.evaluate(() => window.foldcastPlayer.shownFrame());
  const expected = native.subarray(32 + last * vertices * 12, 32 + (last + 1) * vertices * 12);
  check(shown.complete && Buffer.from(shown.base64, 'base64').equals(expected), `its frame ${last} on screen equals the native decode`);
  await page.close();
}

const started = Date.now();
const section = (name) => console.log(`-- ${name} (${((Date.now() - started) / 1000).toFixed(1)} s)`);
try {
  section('streaming');
  let page = await streaming();
  for (let run = 1; run < Number(args.runs); ++run) {
    await page.close();
    page = await streaming();
  }
  if (!args.measure) {
    // Files for the list, the errors and drag-and-drop.
    copyFileSync(fca, join(files, 'a long name, with spaces and accents é ü — to see that the panel holds it.fca'));
    foldcast(['drape', '--grid', '12x12', '--frames', '10', '-o', join(files, 'small.fca')]);
    writeFileSync(join(files, 'empty.fca'), '');
    writeFileSync(join(files, 'header-only.fca'), bytes.subarray(0, ends[1] - 1));
    writeFileSync(join(files, 'preview-only.fca'), bytes.subarray(0, ends[2] - 1));
    writeFileSync(join(files, 'half.fca'), bytes.subarray(0, Math.floor(size * 0.6)));
    const corrupt = Buffer.from(bytes);
    corrupt[Math.floor(size * 0.7)] ^= 0x5a;
    writeFileSync(join(files, 'corrupt.fca'), corrupt);
    // Everything but streaming and resuming is checked on an unthrottled server.
    const fast = await serve(files);
    section('look and frames');
    await lookAndFrames(page);
    const paused = await newPage();
    await paused.goto(`http://127.0.0.1:${fast.port}/?file=files/small.fca&paused`);
    await waitFor(paused, () => window.foldcastPlayer?.stats.completeMs !== null);
    check((await paused.$eval('#play', (b) => b.textContent)) === 'play' && !(await playerState(paused)).playing, '&paused: the button says play');
    await paused.close();
    section('controls');
    await controls(page, fast);
    section('file list, layout, drag-and-drop');
    const listed = await newPage();
    await listed.goto(`http://127.0.0.1:${fast.port}/?file=files/drape.fca`);
    await waitFor(listed, () => document.getElementById('file').options.length >= 5);
    await fileList(listed);
    await dragAndDrop(listed);
    section('errors');
    await errors(listed);
    await listed.close();
    section('resume');
    await resume();
    section('profile cascade');
    await cascadeProfile();
    section('done');
  }
} catch (e) {
  failed++;
  console.log(`FAIL ${e.stack || e}`);
} finally {
  await close();
  for (const s of servers) await s.stop().catch(() => {});
}
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
