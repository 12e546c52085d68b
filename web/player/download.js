// The bytes of an .fca file as they arrive: over HTTP with fetch(), resumed after an
// interruption with a Range request from the first byte missing, or from a local File
// (drag-and-drop).  No DOM: the player reports what goes wrong.

export class DownloadError extends Error {
  // kind: 'network' (interrupted or unreachable: a retry may help) or 'http' (the server said no).
  constructor(kind, message) {
    super(message);
    this.kind = kind;
  }
}

const aborted = (e) => e?.name === 'AbortError';

export class HttpDownload {
  // early: { response, controller } of a fetch already started for `url` (boot.js).
  constructor(url, early = null) {
    this.url = url;
    this.label = decodeURIComponent(url.split('/').pop() || url);
    this.received = 0;
    this.total = null;  // Content-Length of the whole file, once a response says it
    this.requests = 0;
    this.rangeRequests = 0;
    this.controller = early?.controller ?? new AbortController();
    this.pending = early?.response ?? null;
    this.startMs = early?.startMs ?? performance.now();  // when the first request was made
    if (early) this.requests = 1;
  }

  abort() { this.controller.abort(); }

  request() {
    this.requests++;
    const headers = {};
    if (this.received > 0) {
      headers.Range = `bytes=${this.received}-`;
      this.rangeRequests++;
    }
    return fetch(this.url, { headers, signal: this.controller.signal, cache: 'no-store' });
  }

  // Calls onChunk(Uint8Array) for each piece of the file until its end; run() again after a
  // DownloadError of kind 'network' resumes where it stopped.
  async run(onChunk) {
    let response;
    try {
      response = await (this.pending ?? this.request());
    } catch (e) {
      if (aborted(e)) throw e;
      throw new DownloadError('network', `${this.label}: the server could not be reached (${e.message}); ` +
        (this.received ? `${this.received} bytes had arrived` : 'nothing had arrived'));
    } finally {
      this.pending = null;
    }
    let skip = 0;
    if (this.received > 0 && response.status === 206) {
      const start = Number(/bytes (\d+)-/.exec(response.headers.get('Content-Range') || '')?.[1]);
      if (start !== this.received) throw new DownloadError('http', `${this.label}: the server resumed at byte ${start}, not ${this.received}`);
    } else if (this.received > 0 && response.status === 200) {
      skip = this.received;  // the server ignored the Range header: drop what we already have
    } else if (!response.ok) {
      throw new DownloadError('http', `${this.label}: HTTP ${response.status}` +
        (response.status === 416 ? ' (the file is now shorter than what had arrived: it changed on the server)' : ''));
    }
    if (this.total === null) {
      const whole = response.status === 206 ? /\/(\d+)$/.exec(response.headers.get('Content-Range') || '')?.[1]
        : response.headers.get('Content-Length');
      this.total = whole ? Number(whole) : null;
    }
    const reader = response.body.getReader();
    for (;;) {
      let part;
      try {
        part = await reader.read();
      } catch (e) {
        if (aborted(e)) throw e;
        throw new DownloadError('network', `${this.label}: the download was interrupted after ${this.received}` +
          (this.total ? ` of ${this.total}` : '') + ' bytes (the connection closed)');
      }
      if (part.done) return;
      let value = part.value;
      if (skip > 0) {
        const drop = Math.min(skip, value.length);
        skip -= drop;
        value = value.subarray(drop);
        if (!value.length) continue;
      }
      this.received += value.length;
      onChunk(value);
    }
  }
}

export class FileDownload {
  constructor(file) {
    this.file = file;
    this.label = file.name;
    this.received = 0;
    this.total = file.size;
    this.requests = 0;
    this.rangeRequests = 0;
    this.startMs = performance.now();
    this.cancelled = false;
  }

  abort() { this.cancelled = true; }

  async run(onChunk) {
    const reader = this.file.stream().getReader();
    for (;;) {
      const { done, value } = await reader.read();
      if (this.cancelled) throw new DOMException('cancelled', 'AbortError');
      if (done) return;
      this.received += value.length;
      onChunk(value);
    }
  }
}
