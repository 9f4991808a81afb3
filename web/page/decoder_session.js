// A decoding session over the WebAssembly decoder's C interface
// (web/wasm/dtm_wasm.cpp): bytes in, whole levels out, each level's arrays
// copied out of the wasm heap (a view into it dies when memory grows, and
// copies can be transferred to another thread). The viewer's worker and the
// node tests use this same class.

const kEnd = ['done', 'truncated', 'error'];

export class DecoderSession {
  // module: what createDtmDecoder() resolved to. maxVertices: the most
  // vertices the stream may make the session hold (a stream that claims
  // more is refused before its points are decoded).
  // summaries: give each level the native level_summary's line
  // (web/level_summary.cpp), for the equivalence test.
  constructor(module, { maxVertices = 3_000_000, summaries = false } = {}) {
    this.m = module;
    this.handle = module._dtm_session_create(maxVertices);
    if (!this.handle) throw new Error('out of memory creating the decoder');
    this.header = null;
    this.fields = null;
    this.regions = null;  // [{label, name}], empty without regions
    this.bytesFed = 0;
    this.summaries = summaries;
  }

  dispose() {
    if (this.handle) this.m._dtm_session_destroy(this.handle);
    this.handle = 0;
  }

  // Decodes the next chunk (a Uint8Array). Returns the levels it completed,
  // oldest first, and the error that stopped decoding, if one did.
  feed(chunk) {
    const m = this.m;
    const at = m._dtm_session_input(this.handle, chunk.length);
    if (!at && chunk.length) return { levels: [], error: 'out of memory receiving the stream' };
    m.HEAPU8.set(chunk, at);
    const status = m._dtm_session_feed(this.handle, chunk.length);
    this.bytesFed += chunk.length;
    if (!this.header && m._dtm_session_has_header(this.handle)) this.header = this.#readHeader();
    const levels = [];
    while (m._dtm_session_next_level(this.handle)) {
      if (!this.fields) this.fields = this.#readFields();
      if (!this.regions) this.regions = this.#readRegions();
      const level = this.#readLevel();
      if (this.summaries) level.summary = m.UTF8ToString(m._dtm_level_summary(this.handle));
      levels.push(level);
    }
    const error = status < 0 ? m.UTF8ToString(m._dtm_session_error(this.handle)) : null;
    return { levels, error };
  }

  // At the end of the input: how the stream ended, and the decoder's message.
  finish() {
    const code = this.m._dtm_session_finish(this.handle);
    return { status: kEnd[code], message: code ? this.m.UTF8ToString(this.m._dtm_session_error(this.handle)) : '' };
  }

  // The native level_summary's last line: how the stream ended.
  endSummary() {
    return this.m.UTF8ToString(this.m._dtm_session_end_summary(this.handle));
  }

  #readHeader() {
    const m = this.m, h = this.handle;
    const version = m._dtm_header_version(h);
    return {
      version: `${Math.floor(version / 100)}.${version % 100}`,
      qbits: m._dtm_header_qbits(h),
      step: m._dtm_header_step(h),
      centre: [0, 1, 2].map((axis) => m._dtm_header_centre(h, axis)),
      levelCount: m._dtm_header_levels(h),
      vertexCount: m._dtm_header_vertices(h),
      flags: m._dtm_header_flags(h),
    };
  }

  #readFields() {
    const m = this.m, h = this.handle;
    const fields = [];
    for (let f = 0; f < m._dtm_field_count(h); ++f)
      fields.push({
        name: m.UTF8ToString(m._dtm_field_name(h, f)),
        type: m.UTF8ToString(m._dtm_field_type(h, f)),
        components: m._dtm_field_components(h, f),
      });
    return fields;
  }

  #readRegions() {
    const m = this.m, h = this.handle;
    const regions = [];
    for (let r = 0; r < m._dtm_region_count(h); ++r)
      regions.push({ label: m._dtm_region_label(h, r), name: m.UTF8ToString(m._dtm_region_name(h, r)) });
    return regions;
  }

  #readLevel() {
    const m = this.m, h = this.handle;
    const vertices = m._dtm_level_vertices(h);
    const firstNew = m._dtm_level_first_new(h);
    const tetrahedra = m._dtm_level_tetrahedra(h);
    const triangles = m._dtm_level_triangles(h);
    const fresh = vertices - firstNew;
    // Each copy reads HEAP* anew: no call in between can grow the memory.
    const u32 = (ptr, n) => m.HEAPU32.slice(ptr >>> 2, (ptr >>> 2) + n);
    const i32 = (ptr, n) => m.HEAP32.slice(ptr >>> 2, (ptr >>> 2) + n);
    const f32 = (ptr, n) => m.HEAPF32.slice(ptr >>> 2, (ptr >>> 2) + n);
    const u8 = (ptr, n) => m.HEAPU8.slice(ptr, ptr + n);
    const values = this.fields.map((field, f) => f32(m._dtm_level_values(h, f), fresh * field.components));
    return {
      level: m._dtm_level(h),
      vertices,
      firstNew,
      streamBytes: m._dtm_level_stream_bytes(h),
      tetrahedra,
      cells: u32(m._dtm_level_cells(h), 4 * tetrahedra),
      neighbors: i32(m._dtm_level_neighbors(h), 4 * tetrahedra),
      cellRegions: u8(m._dtm_level_cell_regions(h), tetrahedra),
      surface: u32(m._dtm_level_surface(h), 3 * triangles),
      surfaceRegions: u8(m._dtm_level_surface_regions(h), triangles),
      boundary: u8(m._dtm_level_boundary(h), vertices),
      positions: f32(m._dtm_level_positions(h), 3 * fresh),
      values,
    };
  }
}
