// `foldcast serve DIR --port P ...` (any free port by default) as a child process on
// 127.0.0.1; resolves to its port.
import { spawn } from 'node:child_process';

export function startServe(foldcast, dir, extra = [], port = 0) {
  const child = spawn(foldcast, ['serve', dir, '--port', String(port), '--bind', '127.0.0.1', ...extra], { stdio: ['ignore', 'pipe', 'inherit'] });
  return new Promise((resolve, reject) => {
    let out = '';
    child.stdout.on('data', (d) => {
      out += d;
      const m = out.match(/http:\/\/127\.0\.0\.1:(\d+)\//);
      if (m) resolve({ port: Number(m[1]), stop: () => new Promise((done) => { child.on('exit', done); child.kill('SIGINT'); }) });
    });
    child.on('exit', (code) => reject(new Error(`foldcast serve exited with ${code}: ${out}`)));
  });
}
