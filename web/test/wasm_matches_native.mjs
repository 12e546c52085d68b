// The WebAssembly decoder (BUILD/web/foldcast_decoder.wasm) gives the same frames, bit for
// bit, as the native one: on reference files (basicCloth in every profile, drape animations)
// and on prefixes cut at many points, fed in random-sized chunks as a network delivers them.
// Native side: tests/web/fca_prefix_digests (SHA-256 of every frame's float32 bytes).
import { execFileSync } from 'node:child_process';
import { createHash } from 'node:crypto';
import { mkdirSync, readFileSync, rmSync } from 'node:fs';
import { createRequire } from 'node:module';
import { join, resolve } from 'node:path';
import { parseArgs } from 'node:util';
import { FcaStream } from '../player/fca_stream.js';

const { values: args } = parseArgs({
  options: { foldcast: { type: 'string' }, digests: { type: 'string' }, web: { type: 'string' }, tmp: { type: 'string' }, data: { type: 'string' } },
});
rmSync(args.tmp, { recursive: true, force: true });
mkdirSync(args.tmp, { recursive: true });
const run = (cmd, list) => execFileSync(cmd, list, { encoding: 'utf8', maxBuffer: 1 << 26, stdio: ['ignore', 'pipe', 'ignore'] });

// Reference files: a real Blender cache in every profile, drape animations of one and
// several packets (the larger also re-encoded in profile cascade), and a truncated file.
const pc2 = join(args.data, 'animations/basicCloth.pc2');
const files = [];
for (const profile of ['default', 'paper', 'cascade']) {
  const out = join(args.tmp, `basicCloth-${profile}.fca`);
  run(args.foldcast, ['encode', pc2, '-o', out, '--profile', profile]);
  files.push(out);
}
for (const [grid, frames] of [['24x24', 40], ['48x48', 96]]) {
  const out = join(args.tmp, `drape-${grid}x${frames}.fca`);
  run(args.foldcast, ['drape', '--grid', grid, '--frames', String(frames), '--sway-m', '0.02', '-o', out]);
  files.push(out);
}
const cascade = join(args.tmp, 'drape-48x48x96-cascade.fca');
run(args.foldcast, ['encode', files[files.length - 1], '-o', cascade, '--profile', 'cascade']);
files.push(cascade);

// A version 3 file (before the preview packet) decodes the same on both sides too.
files.push(join(args.data, 'fca/v3_drape16.fca'));

const require = createRequire(import.meta.url);
const createFoldcastDecoder = require(resolve(args.web, 'foldcast_decoder.js'));
const module = await createFoldcastDecoder({ wasmBinary: readFileSync(join(args.web, 'foldcast_decoder.wasm')) });

// A deterministic generator for chunk sizes (xorshift32).
let seed = 0x9e3779b9;
const random = () => ((seed ^= seed << 13), (seed ^= seed >>> 17), (seed ^= seed << 5), (seed >>> 0) / 2 ** 32);

function wasmDigest(bytes, cut, total) {
  const stream = new FcaStream(module, total);
  const result = { cut };
  try {
    for (let at = 0; at < cut;) {
      const n = Math.min(cut - at, 1 + Math.floor(random() * random() * 20000));
      stream.feed(bytes.subarray(at, at + n));
      at += n;
    }
  } catch (e) {
    result.error = e.message;
  }
  const s = stream.status();
  Object.assign(result, { header_ready: s.headerReady, complete: s.complete, playable: s.playableFrames, packets: s.packets,
    frame_ready: s.frameReady, preview_only: s.previewOnly, first_frame_bytes: s.firstFrameBytes ?? 0 });
  const sha = createHash('sha256');
  if (s.frameReady) {
    for (let t = 0; t < stream.frames; ++t) {
      const f = stream.frame(t);
      sha.update(new Uint8Array(f.buffer, f.byteOffset, f.byteLength));
    }
  }
  result.sha256 = sha.digest('hex');
  stream.dispose();
  return result;
}

let checked = 0, failed = 0;
for (const file of files) {
  const bytes = readFileSync(file);
  const size = bytes.length;
  // paper reconstructs each frame from its whole wavelet tree (about 0.1 s per prefix of
  // basicCloth natively, several times that in wasm): fewer cuts there.
  // The version 3 file only checks that the old format still reads: fewer cuts there too.
  const [even, randoms] = file.includes('paper') || file.includes('v3_') ? [12, 4] : [48, 16];
  const cuts = new Set([0, 1, 7, 8, 9, 40, size - 1, size]);
  for (let i = 1; i < even; ++i) cuts.add(Math.floor((size * i) / even));
  // Around the ends of the first packets: header, preview (version 4), data packet 0.
  for (let at = 8, k = 0; k < 4 && at + 9 <= size; ++k) {
    at += 9 + bytes.readUInt32LE(at);
    for (const c of [at - 1, at, at + 5]) cuts.add(c);
  }
  for (let i = 0; i < randoms; ++i) cuts.add(Math.floor(random() * size));
  const list = [...cuts].filter((c) => c >= 0 && c <= size).sort((a, b) => a - b);
  const native = run(args.digests, [file, ...list.map(String)]).trim().split('\n').map((l) => JSON.parse(l));
  let headers = 0, completes = 0, previews = 0;
  for (const expected of native) {
    const got = wasmDigest(bytes, expected.cut, size);
    const same = ['header_ready', 'complete', 'playable', 'packets', 'frame_ready', 'preview_only', 'first_frame_bytes', 'sha256'].every((k) => got[k] === expected[k]) &&
      (got.error === undefined) === (expected.error === undefined);
    checked++;
    headers += got.header_ready;
    previews += got.preview_only && !file.includes('v3_');
    completes += got.complete;
    if (!same) {
      failed++;
      console.log(`MISMATCH ${file} cut ${expected.cut}\n  native ${JSON.stringify(expected)}\n  wasm   ${JSON.stringify(got)}`);
    }
  }
  // The cuts must exercise headers, partial files and the whole file, or the test proves little.
  if (headers < list.length / 2 || completes < 1 || (previews < 1 && !file.includes('v3_'))) {
    failed++;
    console.log(`${file}: too few decodable cuts (${headers} with a header, ${previews} with only the preview, ${completes} complete)`);
  }
  console.log(`${file}: ${size} bytes, ${list.length} prefixes compared`);
}

// Corrupt data fails the same way on both sides.
{
  const bytes = Buffer.from(readFileSync(files[0]));
  bytes[bytes.length - 40] ^= 0x5a;
  const corrupt = join(args.tmp, 'corrupt.fca');
  (await import('node:fs')).writeFileSync(corrupt, bytes);
  const [expected] = run(args.digests, [corrupt, String(bytes.length)]).trim().split('\n').map((l) => JSON.parse(l));
  const got = wasmDigest(bytes, bytes.length, bytes.length);
  checked++;
  if (!expected.error || got.error !== expected.error || got.sha256 !== expected.sha256) {
    failed++;
    console.log(`corrupt file: native ${JSON.stringify(expected)}\n  wasm ${JSON.stringify(got)}`);
  }
}

console.log(`${checked - failed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
