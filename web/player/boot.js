// Starts everything the first frame waits for at once, while the page's modules (three.js,
// player.js) are still loading: the .fca download (or the listing that names it),
// looks.json and the WebAssembly decoder.  player.js takes the promises from
// window.foldcastBoot.  A classic script in <head>, so it runs before anything else.
(() => {
  const params = new URLSearchParams(location.search);
  const json = (url) => fetch(url).then((r) => (r.ok ? r.json() : Promise.reject(new Error(`${url}: HTTP ${r.status}`))));
  const quiet = (promise) => (promise.catch(() => {}), promise);  // the player reports failures
  const decoder = quiet(new Promise((resolve, reject) => {
    const script = document.createElement('script');
    script.src = 'foldcast_decoder.js';
    script.onload = () => resolve(createFoldcastDecoder());
    script.onerror = () => reject(new Error('foldcast_decoder.js did not load'));
    document.head.append(script);
  }));
  let early = null;
  const file = params.get('file');
  if (file) {
    const controller = new AbortController();
    early = { url: file, controller, startMs: performance.now(), response: quiet(fetch(file, { signal: controller.signal, cache: 'no-store' })) };
  }
  window.foldcastBoot = { early, decoder, listing: quiet(json('api/files')), looks: quiet(json('looks.json')) };
})();
