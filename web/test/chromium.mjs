// Debian's chromium, headless, for tests and benchmarks: the flags keep it from reaching
// for the network (closed here: it would hang on connections) and give WebGL on the CPU.
import { mkdtempSync, rmSync } from 'node:fs';
import { join } from 'node:path';
import puppeteer from 'puppeteer-core';

export async function launchChromium(executablePath, tmp) {
  const profile = mkdtempSync(join(tmp, 'chromium-profile-'));
  const browser = await puppeteer.launch({
    executablePath,
    headless: true,
    defaultViewport: { width: 960, height: 640 },
    userDataDir: profile,
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking',
      '--disable-component-update', '--disable-sync', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
      '--window-size=960,640'],
  });
  const close = async () => {
    await browser.close();
    rmSync(profile, { recursive: true, force: true });
  };
  return { browser, close };
}
