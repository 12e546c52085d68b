// Time to first frame, to every frame final and to full quality in the browser player
// (headless Chromium) over a link throttled by `foldcast serve --throttle-kbps`
// (docs/benchmarks.md, "Streaming to a browser").  Prints one JSON line per run and a
// summary (medians); times in ms from the moment the player starts fetching the .fca.
//   node bench/player_stream.mjs --foldcast build/foldcast [--kbps 2000] [--runs 3] [--tmp DIR]
import { execFileSync } from 'node:child_process';
import { mkdirSync, statSync } from 'node:fs';
import { join, resolve } from 'node:path';
import { parseArgs } from 'node:util';
import { launchChromium } from '../web/test/chromium.mjs';
import { startServe } from '../web/test/serve_process.mjs';

const { values: args } = parseArgs({
  options: {
    foldcast: { type: 'string', default: 'build/foldcast' }, chromium: { type: 'string', default: '/usr/bin/chromium' },
    kbps: { type: 'string', default: '2000' }, runs: { type: 'string', default: '3' }, tmp: { type: 'string', default: 'build/bench-player' },
    quick: { type: 'boolean', default: false },
  },
});
const tmp = resolve(args.tmp);
const files = join(tmp, 'files');
mkdirSync(files, { recursive: true });
const here = new URL('..', import.meta.url).pathname;

const inputs = [];
{
  const out = join(files, 'basicCloth.fca');
  execFileSync(args.foldcast, ['encode', join(here, 'tests/data/animations/basicCloth.pc2'), '-o', out], { stdio: 'ignore' });
  inputs.push({ name: 'basicCloth (81 vertices, 150 frames)', file: 'basicCloth.fca', vertices: 81, frames: 150 });
}
{
  const [grid, frames] = args.quick ? [32, 60] : [128, 240];
  const out = join(files, `drape${grid}.fca`);
  execFileSync(args.foldcast, ['drape', '--grid', `${grid}x${grid}`, '--frames', String(frames), '-o', out], { stdio: 'ignore' });
  inputs.push({ name: `drape ${grid}x${grid} x ${frames}`, file: `drape${grid}.fca`, vertices: grid * grid, frames });
}

const serve = await startServe(args.foldcast, files, ['--throttle-kbps', args.kbps]);
const { browser, close } = await launchChromium(args.chromium, tmp);
const median = (xs) => [...xs].sort((a, b) => a - b)[Math.floor(xs.length / 2)];
try {
  for (const input of inputs) {
    const bytes = statSync(join(files, input.file)).size;
    const runs = [];
    for (let r = 0; r < Number(args.runs); ++r) {
      const page = await browser.newPage();
      await page.goto(`http://127.0.0.1:${serve.port}/?file=files/${input.file}`);
      await page.waitForFunction(() => window.foldcastPlayer?.stats.completeMs !== null || window.foldcastPlayer?.stats.error,
        { timeout: 600000, polling: 50 });
      const s = await page.evaluate(() => window.foldcastPlayer.stats);
      if (s.error) throw new Error(s.error);
      const at = (x) => Math.round(x - s.fetchStartMs);
      const run = { input: input.name, bytes, header: at(s.headerMs), first_frame: at(s.firstFrameMs), bytes_at_first_frame: s.bytesAtFirstFrame,
        all_final: at(s.allPlayableMs), complete: at(s.completeMs) };
      console.log(JSON.stringify(run));
      runs.push(run);
      await page.close();
    }
    const pc2 = 32 + input.vertices * input.frames * 12;
    const rate = (Number(args.kbps) * 1000) / 8;  // bytes per second
    console.log(`SUMMARY ${input.name}: .fca ${bytes} bytes; median ms from fetch start: first frame ${median(runs.map((r) => r.first_frame))}` +
      ` (after ${median(runs.map((r) => r.bytes_at_first_frame))} bytes), every frame final ${median(runs.map((r) => r.all_final))},` +
      ` full quality ${median(runs.map((r) => r.complete))}; link time of the whole .fca ${Math.round((bytes / rate) * 1000)} ms;` +
      ` PC2 ${pc2} bytes: first frame ${Math.round(((32 + input.vertices * 12) / rate) * 1000)} ms, all ${Math.round((pc2 / rate) * 1000)} ms`);
  }
} finally {
  await close();
  await serve.stop();
}
