// The .fca streaming decoder in WebAssembly (web/wasm/decoder_api.cpp: codec/ compiled by
// emscripten) behind a small class.  No DOM: the player and the Node tests share it.

export class FcaStream {
  // module: what createFoldcastDecoder() resolved to; totalBytes: the file size if known.
  constructor(module, totalBytes) {
    this.M = module;
    this.handle = module._fca_new(totalBytes || 0);
    this.vertices = 0;
  }

  dispose() {
    if (this.handle) this.M._fca_delete(this.handle);
    this.handle = 0;
  }

  // Appends bytes (a Uint8Array) and decodes every complete packet; throws Error with the
  // codec's message on corrupt data.
  feed(bytes) {
    const M = this.M;
    const at = M._fca_input(this.handle, bytes.length);
    M.HEAPU8.set(bytes, at);  // read HEAPU8 after the call: the heap may have grown
    if (M._fca_feed(this.handle, bytes.length) !== 0) throw new Error(M.UTF8ToString(M._fca_error(this.handle)));
  }

  status() {
    const M = this.M;
    const i = M._fca_status(this.handle) >> 3;
    const s = M.HEAPF64;
    const status = {
      headerReady: s[i] === 1, complete: s[i + 1] === 1, playableFrames: s[i + 2], packets: s[i + 3],
      bytesUsed: s[i + 4], maxErrorM: s[i + 5] >= 0 ? s[i + 5] : null,
      frameReady: s[i + 6] === 1, previewOnly: s[i + 7] === 1, firstFrameBytes: s[i + 8] || null,
    };
    if (status.headerReady && !this.vertices) {
      this.vertices = M._fca_vertex_count(this.handle);
      this.frames = M._fca_frame_count(this.handle);
      this.fps = M._fca_fps(this.handle);
      this.profile = ['paper', 'default', 'cascade'][M._fca_profile(this.handle)] ?? 'default';
      this.metadata = {};
      for (let k = 0; k < M._fca_metadata_count(this.handle); ++k)
        this.metadata[M.UTF8ToString(M._fca_metadata_key(this.handle, k))] = M.UTF8ToString(M._fca_metadata_value(this.handle, k));
    }
    return status;
  }

  // Triangle indices (Uint32Array, 3 per triangle), once the header is in.
  triangles() {
    const M = this.M;
    const n = 3 * M._fca_triangle_count(this.handle);
    const at = M._fca_triangles(this.handle) >> 2;
    return M.HEAPU32.slice(at, at + n);
  }

  // Per-vertex UVs (Float32Array of 2N), or null when the file has none.
  uvs() {
    const M = this.M;
    const at = M._fca_uvs(this.handle) >> 2;
    return at ? M.HEAPF32.slice(at, at + 2 * this.vertices) : null;
  }

  // Frame t as reconstructed from the bytes so far, into `out` (Float32Array of 3N) or a new array.
  frame(t, out) {
    const M = this.M;
    const at = M._fca_frame(this.handle, t);
    if (!at) throw new Error(M.UTF8ToString(M._fca_error(this.handle)));
    const view = M.HEAPF32.subarray(at >> 2, (at >> 2) + 3 * this.vertices);
    if (!out) return view.slice();
    out.set(view);
    return out;
  }
}
