// The player in headless Chromium (Debian's, driven by puppeteer-core), loading a drape
// animation from `foldcast serve --throttle-kbps`: frame 0 is on screen before the download
// has finished, the download completes without error, and the last frame on screen is
// bit for bit the native decoder's (`foldcast decode`).
import { execFileSync } from 'node:child_process';
import { mkdirSync, readFileSync, rmSync, statSync } from 'node:fs';
import { join } from 'node:path';
import { parseArgs } from 'node:util';
import { launchChromium } from './chromium.mjs';
import { startServe } from './serve_process.mjs';

const { values: args } = parseArgs({ options: { foldcast: { type: 'string' }, chromium: { type: 'string' }, tmp: { type: 'string' } } });
rmSync(args.tmp, { recursive: true, force: true });
const files = join(args.tmp, 'files');
mkdirSync(files, { recursive: true });

const fca = join(files, 'drape.fca');
execFileSync(args.foldcast, ['drape', '--grid', '48x48', '--frames', '96', '--sway-m', '0.02', '-o', fca], { stdio: 'ignore' });
const size = statSync(fca).size;
const kbps = Math.max(8, Math.round((size * 8) / 1000 / 4));  // the download takes about 4 s
const serve = await startServe(args.foldcast, files, ['--throttle-kbps', String(kbps)]);
const { browser, close } = await launchChromium(args.chromium, args.tmp);

let passed = 0, failed = 0;
const check = (ok, what) => {
  ok ? passed++ : failed++;
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
};
try {
  const page = await browser.newPage();
  page.on('console', (m) => { if (!m.text().includes('GL Driver Message')) console.log(`page: ${m.text()}`); });
  page.on('pageerror', (e) => console.log(`page error: ${e.message}`));
  await page.goto(`http://127.0.0.1:${serve.port}/?file=files/drape.fca&look=denim`);
  await page.waitForFunction(() => window.foldcastPlayer?.stats.downloadDoneMs !== null || window.foldcastPlayer?.stats.error,
    { timeout: 120000, polling: 100 });
  const stats = await page.evaluate(() => window.foldcastPlayer.stats);
  console.log(`${size} bytes at ${kbps} kbit/s: ${JSON.stringify(stats)}`);
  check(stats.error === null, `no error (${stats.error})`);
  check(stats.totalBytes === size && stats.bytes === size, 'every byte arrived');
  check(stats.firstFrameIndex === 0, 'the first frame shown is frame 0');
  check(stats.firstFrameMs !== null && stats.firstFrameMs < stats.downloadDoneMs, 'frame 0 was shown before the download finished');
  check(stats.bytesAtFirstFrame < size / 2, `frame 0 was shown after ${stats.bytesAtFirstFrame} of ${size} bytes`);
  check(stats.completeMs !== null && stats.allPlayableMs !== null, 'the stream completed: every frame final');

  // The last frame on screen, once complete, equals the native decoder's bit for bit.
  const pc2 = join(args.tmp, 'native.pc2');
  execFileSync(args.foldcast, ['decode', fca, '-o', pc2], { stdio: 'ignore' });
  const native = readFileSync(pc2);
  const vertices = native.readInt32LE(16), frames = native.readInt32LE(28);
  const last = frames - 1;
  await page.evaluate((t) => window.foldcastPlayer.seek(t), last);
  await page.waitForFunction((t) => window.foldcastPlayer.shownFrame()?.index === t, { timeout: 20000 }, last);
  const shown = await page.evaluate(() => window.foldcastPlayer.shownFrame());
  const expected = native.subarray(32 + last * vertices * 12, 32 + (last + 1) * vertices * 12);
  check(shown.complete && Buffer.from(shown.base64, 'base64').equals(expected), `frame ${last} on screen equals the native decode (${vertices} vertices)`);
  await page.screenshot({ path: join(args.tmp, 'player.png') });
  console.log(`screenshot: ${join(args.tmp, 'player.png')}`);
} catch (e) {
  failed++;
  console.log(`FAIL ${e.stack || e}`);
} finally {
  await close();
  await serve.stop();
}
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
