// Khronos's glTF-Validator (npm gltf-validator) on every kind of .glb foldcast writes: a
// static garment in every shipped look, animations compressed (KHR_mesh_quantization +
// EXT_meshopt_compression) and not, a decoded .fca and an exported scene.  Passes when
// every file has zero errors and zero warnings (informational notes are printed).
import { execFileSync } from 'node:child_process';
import { mkdirSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { parseArgs } from 'node:util';
import validator from 'gltf-validator';

const { values: args } = parseArgs({ options: { foldcast: { type: 'string' }, tmp: { type: 'string' } } });
rmSync(args.tmp, { recursive: true, force: true });
mkdirSync(args.tmp, { recursive: true });
const foldcast = (...a) => execFileSync(args.foldcast, a, { encoding: 'utf8', stdio: ['ignore', 'pipe', 'inherit'] });
const out = (name) => join(args.tmp, name);

const files = [];
const looks = JSON.parse(foldcast('looks', '--json')).looks.map((l) => l.name);
for (const look of looks) {
  foldcast('drape', '--grid', '12x16', '--look', look, '-q', '-o', out(`static-${look}.glb`));
  files.push(`static-${look}.glb`);
}
foldcast('drape', '--grid', '16x20', '--frames', '12', '--sway-m', '0.02', '--look', 'denim', '-q', '-o', out('anim.glb'));
foldcast('drape', '--grid', '16x20', '--frames', '12', '--sway-m', '0.02', '--look', 'denim', '-q', '--uncompressed',
  '-o', out('anim-float.glb'));
foldcast('drape', '--grid', '16x20', '--frames', '8', '-q', '-o', out('anim.fca'));
foldcast('decode', out('anim.fca'), '-o', out('decoded.glb'));
writeFileSync(out('scene.toml'), 'look = "wool_flannel"\n[garment]\nsource = "drape"\ngrid = [20, 24]\n');
foldcast('export', out('scene.toml'), '-q', '-o', out('export.glb'));
files.push('anim.glb', 'anim-float.glb', 'decoded.glb', 'export.glb');

let failed = 0;
for (const name of files) {
  const report = await validator.validateBytes(new Uint8Array(readFileSync(out(name))), { maxIssues: 100 });
  const { numErrors, numWarnings, numInfos, messages } = report.issues;
  const ok = numErrors === 0 && numWarnings === 0;
  if (!ok) failed++;
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${name}: ${numErrors} errors, ${numWarnings} warnings, ${numInfos} infos`);
  for (const m of messages) if (m.severity <= 1) console.log(`     [${m.severity ? 'warning' : 'error'}] ${m.code} ${m.pointer ?? ''}: ${m.message}`);
  if (ok && numInfos) console.log(`     infos: ${[...new Set(messages.map((m) => m.code))].join(', ')}`);
}
console.log(`${files.length - failed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
