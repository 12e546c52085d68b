// Serves a page's files to headless Chromium straight from disk through puppeteer's request
// interception (no server process): URL paths under http://foldcast.test/ map to folders,
// and any other request (a CDN, the network) is refused, so a test sees what ships here only.
import { readFileSync, existsSync, statSync } from 'node:fs';
import { extname, join, normalize } from 'node:path';

const types = {
  '.html': 'text/html', '.js': 'text/javascript', '.mjs': 'text/javascript', '.glb': 'model/gltf-binary',
  '.png': 'image/png', '.mp4': 'video/mp4', '.webm': 'video/webm', '.json': 'application/json', '.wasm': 'application/wasm',
};
export const origin = 'http://foldcast.test';

// mounts: { '/three/': '/abs/web/node_modules/three/', ... }; pages: { '/page.html': '<html>...' }
// (a page's type follows its extension).
export async function serveLocally(page, mounts, pages = {}) {
  await page.setRequestInterception(true);
  page.on('request', (request) => {
    const url = new URL(request.url());
    if (url.origin !== origin) return request.abort('blockedbyclient');
    if (pages[url.pathname] !== undefined)
      return request.respond({ status: 200, contentType: types[extname(url.pathname)] ?? 'text/html', body: pages[url.pathname] });
    for (const [prefix, dir] of Object.entries(mounts)) {
      if (!url.pathname.startsWith(prefix)) continue;
      const file = normalize(join(dir, decodeURIComponent(url.pathname.slice(prefix.length))));
      if (!file.startsWith(normalize(dir)) || !existsSync(file) || !statSync(file).isFile()) break;
      const body = readFileSync(file);
      const range = request.headers().range?.match(/bytes=(\d+)-(\d*)/);
      const headers = { 'Accept-Ranges': 'bytes', 'Access-Control-Allow-Origin': '*' };
      const contentType = types[extname(file)] ?? 'application/octet-stream';
      if (range) {  // <video> asks for ranges
        const start = Number(range[1]), end = range[2] ? Math.min(Number(range[2]), body.length - 1) : body.length - 1;
        return request.respond({ status: 206, contentType, body: body.subarray(start, end + 1),
          headers: { ...headers, 'Content-Range': `bytes ${start}-${end}/${body.length}` } });
      }
      return request.respond({ status: 200, contentType, body, headers });
    }
    request.respond({ status: 404, contentType: 'text/plain', body: 'not found' });
  });
}
