// SPDX-License-Identifier: MIT
// The page: tabs, file picking and drag-and-drop, the samples menu, the job bar (progress and
// cancel), the Mesh and Lens tabs, error display and downloads. The core runs in the worker;
// this file never sees a C++ type, only {ok, ...} objects and typed arrays.
import { JobClient } from './job_client.js';
import { MeshView, QUALITY_GRADIENT } from './mesh_view.js';
import { LensView } from './lens_view.js';

const $ = (id) => document.getElementById(id);
const jobs = new JobClient();

// ---- errors -----------------------------------------------------------------------------------
function showError(message) {
  $('error-text').textContent = message;
  $('error').hidden = false;
}
function clearError() { $('error').hidden = true; $('error-text').textContent = ''; }
$('error-close').addEventListener('click', clearError);
window.addEventListener('unhandledrejection', (e) => showError('unexpected error: ' + (e.reason?.message || e.reason)));

// ---- job bar ----------------------------------------------------------------------------------
function setProgress(stage, fraction) {
  $('job-progress').value = fraction;
  $('job-stage').textContent = stage;
}
// Cancel is offered once a job has run for 250 ms: the lens's live jobs take a few ms each, and
// toggling the button for every one of them flickers and restyles the header at every frame.
let cancelTimer = 0;
jobs.onState((state) => {
  clearTimeout(cancelTimer);
  if (state === 'busy') cancelTimer = setTimeout(() => { $('job-cancel').disabled = false; }, 250);
  else if (!$('job-cancel').disabled) $('job-cancel').disabled = true;
});
$('job-cancel').addEventListener('click', () => jobs.cancel());

/// Runs a job with the job bar; long-running or not, the UI stays responsive (the worker computes).
async function runJob(job, args, { quiet = false, transfer = [] } = {}) {
  if (!quiet) setProgress(job + '…', 0);
  // Quiet jobs (the lens's live runs) leave the bar alone: its text would re-lay out the page every frame.
  const result = await jobs.run(job, args, { transfer, onProgress: quiet ? null : (stage, f) => setProgress(stage, f) });
  if (!quiet || !result.ok) setProgress(result.ok ? `${job}: done (${result.ms_worker.toFixed(0)} ms)` : `${job}: ${result.message === 'cancelled' ? 'cancelled' : 'failed'}`, result.ok ? 1 : 0);
  return result;
}

jobs.ready().then(({ version, jobs: available }) => {
  $('core-version').textContent = 'core ' + version;
  setProgress('ready', 0);
  jobs.available = available;
  if (available.includes('mesh2spline') && meshTab.bytes) $('mesh-run').disabled = false;
  if (available.includes('vol2spline')) for (const id of ['volume-run', 'volume-download-json', 'volume-options']) $(id).hidden = false;
}, (e) => { setProgress('core failed to load', 0); showError(e.message); });

// ---- tabs -------------------------------------------------------------------------------------
const tabs = ['mesh', 'lens', 'volume'];
function selectTab(name) {
  for (const t of tabs) {
    $('tab-' + t).setAttribute('aria-selected', String(t === name));
    $('panel-' + t).hidden = t !== name;
  }
  if (name === 'mesh') meshTab.view?.requestDraw();
  if (location.hash !== '#' + name) history.replaceState(null, '', '#' + name);
}
for (const t of tabs) $('tab-' + t).addEventListener('click', () => selectTab(t));

// ---- files ------------------------------------------------------------------------------------
function download(bytes, name, type) {
  const url = URL.createObjectURL(new Blob([bytes], { type }));
  const a = document.createElement('a');
  a.href = url; a.download = name;
  document.body.append(a); a.click(); a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 10000);
}
const readFile = async (file) => new Uint8Array(await file.arrayBuffer());

/// Wires a panel's file input and drag-and-drop to `open(bytes, name)`.
function acceptFiles(panel, input, open) {
  input.addEventListener('change', async () => {
    const file = input.files[0];
    input.value = '';
    if (file) open(await readFile(file), file.name);
  });
  panel.addEventListener('dragover', (e) => { e.preventDefault(); panel.classList.add('dragover'); });
  panel.addEventListener('dragleave', () => panel.classList.remove('dragover'));
  panel.addEventListener('drop', async (e) => {
    e.preventDefault();
    panel.classList.remove('dragover');
    const file = e.dataTransfer.files[0];
    if (file) open(await readFile(file), file.name);
  });
}

/// Fills a <select> with the bundled samples of one kind and calls open(bytes, name) on choice.
function samplesMenu(select, kind, list, open) {
  for (const s of list.filter((s) => s.kind === kind)) {
    const option = document.createElement('option');
    option.value = s.path;
    option.textContent = `${s.name} (${Math.round(s.bytes / 1024)} kB)`;
    select.append(option);
  }
  select.addEventListener('change', async () => {
    const path = select.value;
    if (!path) return;
    select.value = '';
    try {
      const response = await fetch(path);
      if (!response.ok) throw new Error(`${path}: HTTP ${response.status}`);
      open(new Uint8Array(await response.arrayBuffer()), path.split('/').pop());
    } catch (e) {
      showError('could not load the sample: ' + e.message);
    }
  });
}

function fillStats(table, rows) {
  table.replaceChildren(...rows.map(([k, v]) => {
    const tr = document.createElement('tr');
    const th = document.createElement('th'); th.textContent = k;
    const td = document.createElement('td'); td.textContent = v; td.dataset.key = k;
    tr.append(th, td);
    return tr;
  }));
}
const fmt = (x, digits = 4) => (typeof x === 'number' ? (Number.isInteger(x) ? String(x) : x.toPrecision(digits)) : String(x));

// ---- mesh tab ---------------------------------------------------------------------------------
const baseName = (name) => name.replace(/\.[^.]*$/, '');
const meshTab = {
  view: null,
  info: null,        // meshInfo result of the open mesh (without its arrays)
  bytes: null, name: null,
  result: null,      // the last mesh2spline result
  cutRunning: false, cutPending: false,

  async open(bytes, name) {
    clearError();
    const r = await runJob('meshInfo', { bytes: bytes.slice(), name });
    if (!r.ok) { if (r.message !== 'cancelled') showError(r.message); return; }
    const { positions, triangles, ok, ms_worker, ...facts } = r;
    Object.assign(this, { info: { file: name, ...facts }, bytes, name, result: null });
    $('mesh-show-input').checked = true;
    if (this.view) this.view.visible.input = true;
    this.view?.setMesh(positions, triangles, r.bbox_min, r.bbox_max);
    this.showInfo();
    $('mesh-run').disabled = !jobs.available?.includes('mesh2spline');
    $('mesh-download-stats').disabled = false;
    for (const k of ['json', 'glb', 'vtu']) $('mesh-download-' + k).disabled = true;
    $('mesh-legend').hidden = true;
  },

  showInfo() {
    const r = this.info;
    const bbox = (v) => v.map((x) => fmt(x, 3)).join(', ');
    fillStats($('mesh-stats'), [
      ['file', r.file], ['vertices', r.vertices], ['faces', r.faces], ['edges', r.edges],
      ['closed', r.closed ? 'yes' : 'no'], ['manifold', r.manifold ? 'yes' : 'no'],
      ['components', r.components], ['boundary_loops', r.boundary_loops],
      ['genus', r.genus === null ? 'undefined' : r.genus], ['euler_characteristic', r.euler_characteristic],
      ['consistently_oriented', r.consistently_oriented ? 'yes' : 'no'], ['degenerate_faces', r.degenerate_faces],
      ['signed_volume', fmt(r.signed_volume)], ['bbox_min', bbox(r.bbox_min)], ['bbox_max', bbox(r.bbox_max)],
    ]);
  },

  options() {
    return {
      max_levels: Number($('mesh-levels').value), fit: $('mesh-fit').value,
      cut_axis: Number($('mesh-cut-axis').value), cut_position: Number($('mesh-cut-position').value),
    };
  },

  async run() {
    if (!this.bytes || jobs.busy) return;
    clearError();
    $('mesh-run').disabled = true;
    const options = this.options();
    const r = await runJob('mesh2spline', { bytes: this.bytes.slice(), name: this.name, options });
    $('mesh-run').disabled = false;
    if (!r.ok) { if (r.message !== 'cancelled') showError(r.message); return; }
    this.result = { ...r, options };
    this.view?.setSpline(r);
    // The input mesh would hide the cut: shown again by its checkbox.
    $('mesh-show-input').checked = false;
    if (this.view) this.view.visible.input = false;
    this.showStats();
    for (const k of ['json', 'glb', 'vtu', 'stats']) $('mesh-download-' + k).disabled = false;
    $('mesh-legend').hidden = false;
    // The cut controls may have moved while the job ran.
    const o = this.options();
    if (o.cut_axis !== options.cut_axis || o.cut_position !== options.cut_position) this.updateCut();
  },

  showStats() {
    const s = this.result.stats, i = this.info;
    fillStats($('mesh-stats'), [
      ['file', i.file], ['vertices', i.vertices], ['faces', i.faces], ['genus', i.genus === null ? 'undefined' : i.genus],
      ['fit', s.fit], ['rms_rel', fmt(s.rms_rel, 3)], ['max_rel', fmt(s.max_rel, 3)],
      ['hausdorff_rel', fmt(s.hausdorff_rel, 3)], ['rms_geo_rel', fmt(s.rms_geo_rel, 3)],
      ['control_points', s.control_points], ['levels', s.levels], ['cuboids', s.cuboids],
      ['min_scaled_jacobian', fmt(s.min_scaled_jacobian, 3)], ['negative_jacobian_fraction', fmt(s.negative_jacobian_fraction, 3)],
      ['semi_standard_max_error', fmt(s.semi_standard_max_error, 3)], ['flipped_triangles', s.flipped_triangles],
      ['grid_inverted_hexes', s.grid_inverted_hexes], ['grid_min_scaled_jacobian', fmt(s.grid_min_scaled_jacobian, 3)],
      ['samples', s.samples], ['min_corner_distance_rel', fmt(s.min_corner_distance_rel, 3)],
      ['cut_min_scaled_jacobian', fmt(this.result.cut.min_scaled_jacobian, 3)],
      ['time_s', fmt(s.times_s.total, 3)], ['worker_ms', fmt(this.result.ms_worker, 4)],
    ]);
  },

  /// Recomputes the cut for the current axis and position; while one is computed only the latest
  /// request is kept.
  async updateCut() {
    if (!this.result) return;
    if (this.cutRunning || jobs.busy) { this.cutPending = true; return; }
    this.cutRunning = true;
    this.cutPending = false;
    try {
      const { cut_axis: axis, cut_position: position } = this.options();
      const r = await runJob('splineCut', { json: this.result.spline_json.slice(), axis, position, samples: 41 }, { quiet: true });
      if (!r.ok) { if (r.message !== 'cancelled') showError(r.message); return; }
      this.result.cut = r;
      this.view?.setCut(r);
      const td = document.querySelector('#mesh-stats td[data-key="cut_min_scaled_jacobian"]');
      if (td) td.textContent = fmt(r.min_scaled_jacobian, 3);
    } finally {
      this.cutRunning = false;
      if (this.cutPending) this.updateCut();
    }
  },

  statsJson() {
    if (!this.result) return this.info;
    return { ...this.result.stats, options: this.result.options, cut_min_scaled_jacobian: this.result.cut.min_scaled_jacobian };
  },
};
try {
  meshTab.view = new MeshView($('mesh-canvas'));
  $('mesh-legend-bar').style.background = QUALITY_GRADIENT;
} catch (e) {
  showError(e.message);
}
acceptFiles($('panel-mesh'), $('mesh-file'), (b, n) => meshTab.open(b, n));
for (const layer of ['input', 'wireframe', 'boundary', 'lines', 'control', 'cut']) {
  $('mesh-show-' + layer).addEventListener('change', (e) => {
    if (!meshTab.view) return;
    meshTab.view.visible[layer] = e.target.checked;
    meshTab.view.requestDraw();
  });
}
$('mesh-run').addEventListener('click', () => meshTab.run());
$('mesh-cut-axis').addEventListener('change', () => meshTab.updateCut());
$('mesh-cut-position').addEventListener('input', () => { $('mesh-cut-value').textContent = $('mesh-cut-position').value; meshTab.updateCut(); });
$('mesh-download-json').addEventListener('click', () => download(meshTab.result.spline_json, baseName(meshTab.name) + '.spline.json', 'application/json'));
$('mesh-download-glb').addEventListener('click', () => download(meshTab.result.glb, baseName(meshTab.name) + '.spline.glb', 'model/gltf-binary'));
$('mesh-download-vtu').addEventListener('click', () => download(meshTab.result.vtu, baseName(meshTab.name) + '.spline.vtu', 'application/xml'));
$('mesh-download-stats').addEventListener('click', () => {
  download(JSON.stringify(meshTab.statsJson(), null, 2) + '\n', baseName(meshTab.name) + (meshTab.result ? '.stats.json' : '.info.json'), 'application/json');
});

// ---- volume tab -------------------------------------------------------------------------------
// Density colours (dark blue → magenta → orange → pale yellow) as a 256-entry RGB table.
const DENSITY_STOPS = [[0, [0, 0, 4]], [0.25, [60, 15, 110]], [0.5, [170, 50, 110]], [0.75, [245, 125, 35]], [1, [252, 255, 164]]];
const DENSITY_LUT = (() => {
  const lut = new Uint8Array(256 * 3);
  for (let i = 0; i < 256; i++) {
    const t = i / 255;
    let k = 0;
    while (k < DENSITY_STOPS.length - 2 && t > DENSITY_STOPS[k + 1][0]) k++;
    const [t0, c0] = DENSITY_STOPS[k], [t1, c1] = DENSITY_STOPS[k + 1];
    const f = (t - t0) / (t1 - t0);
    for (let c = 0; c < 3; c++) lut[3 * i + c] = Math.round(c0[c] + f * (c1[c] - c0[c]));
  }
  return lut;
})();

const volumeTab = {
  volume: null,   // {name, nx, ny, nz, samples Float32Array, min, max, ...}
  fit: null,      // vol2spline result (density resampled on the same grid), when that job exists

  layout() {
    const dims = ['nx', 'ny', 'nz'].map((k) => Number($('volume-' + k).value));
    if (!dims.every((d) => Number.isInteger(d) && d > 0)) return null;  // the core takes dims from the name
    return { dims, type: $('volume-type').value };
  },

  async open(bytes, name) {
    clearError();
    const layout = /\.raw$/i.test(name) && !/_\d+x\d+x\d+_[a-z0-9]+\.raw$/i.test(name) ? this.layout() : null;
    const r = await runJob('loadVolume', { bytes, name, layout }, { transfer: [bytes.buffer] });
    if (!r.ok) { if (r.message !== 'cancelled') showError(r.message); return; }
    this.volume = { name, ...r };
    this.fit = null;
    $('volume-hint').hidden = true;
    $('volume-fit-figure').hidden = true;
    $('volume-run').disabled = !jobs.available?.includes('vol2spline');
    $('volume-download-json').disabled = true;
    this.setAxis();
    this.showStats();
  },

  /// Runs vol2spline on the loaded volume and shows the spline's density beside the input.
  async run() {
    const v = this.volume;
    if (!v || jobs.busy) return;
    clearError();
    $('volume-run').disabled = true;
    const options = { max_levels: Number($('volume-levels').value), max_rms_rel: Number($('volume-max-rms').value) };
    const volume = { nx: v.nx, ny: v.ny, nz: v.nz, spacing: v.spacing, samples: v.samples.slice() };
    const r = await runJob('vol2spline', { volume, name: v.name, options }, { transfer: [volume.samples.buffer] });
    $('volume-run').disabled = false;
    if (!r.ok) { if (r.message !== 'cancelled') showError(r.message); return; }
    if (this.volume !== v) return;  // another volume was opened meanwhile
    this.fit = { density: r.reconstruction, stats: r.stats, spline_json: r.spline_json, options };
    $('volume-fit-figure').hidden = false;
    $('volume-download-json').disabled = false;
    this.draw();
    this.showStats();
  },

  dims(axis) {  // slice width, height and count along the axis
    const { nx, ny, nz } = this.volume;
    return axis === 0 ? [ny, nz, nx] : axis === 1 ? [nx, nz, ny] : [nx, ny, nz];
  },

  setAxis() {
    if (!this.volume) return;
    const axis = Number($('volume-axis').value);
    const [, , n] = this.dims(axis);
    const slider = $('volume-slice');
    slider.max = String(n - 1);
    slider.value = String(n >> 1);
    this.draw();
  },

  /// Paints slice `index` along `axis` of `samples` (x fastest) into `canvas`, colours scaled
  /// to [lo, hi]; the slice's second axis points up.
  paint(canvas, samples, axis, index, lo, hi) {
    const { nx, ny } = this.volume;
    const [w, h] = this.dims(axis);
    canvas.width = w; canvas.height = h;
    const ctx = canvas.getContext('2d');
    const image = ctx.createImageData(w, h);
    const scale = hi > lo ? 255 / (hi - lo) : 0;
    for (let j = 0; j < h; j++)
      for (let i = 0; i < w; i++) {
        const [x, y, z] = axis === 0 ? [index, i, j] : axis === 1 ? [i, index, j] : [i, j, index];
        const v = samples[x + nx * (y + ny * z)];
        const c = Math.max(0, Math.min(255, Math.round((v - lo) * scale)));
        const o = 4 * (i + w * (h - 1 - j));
        image.data[o] = DENSITY_LUT[3 * c]; image.data[o + 1] = DENSITY_LUT[3 * c + 1]; image.data[o + 2] = DENSITY_LUT[3 * c + 2];
        image.data[o + 3] = 255;
      }
    ctx.putImageData(image, 0, 0);
  },

  draw() {
    const v = this.volume;
    if (!v) return;
    const axis = Number($('volume-axis').value), index = Number($('volume-slice').value);
    $('volume-slice-value').textContent = `${'xyz'[axis]} = ${index}`;
    this.paint($('volume-canvas'), v.samples, axis, index, v.min, v.max);
    if (this.fit) this.paint($('volume-fit-canvas'), this.fit.density, axis, index, v.min, v.max);
  },

  showStats() {
    const v = this.volume;
    const rows = [
      ['file', v.name], ['dims', `${v.nx} × ${v.ny} × ${v.nz}`], ['voxels', v.nx * v.ny * v.nz], ['type', v.type],
      ['spacing', v.spacing.map((x) => fmt(x, 3)).join(', ')], ['min', fmt(v.min)], ['max', fmt(v.max)],
    ];
    if (this.fit) {
      const f = this.fit.stats;
      rows.push(['density_rms_rel', fmt(f.density_rms_rel, 3)], ['density_max_rel', fmt(f.density_max_rel, 3)],
                ['control_points', f.control_points], ['levels', f.levels], ['patches', f.patches],
                ['min_scaled_jacobian', fmt(f.min_scaled_jacobian, 3)], ['time_s', fmt(f.times_s.total, 3)]);
      if (f.frames_computed) rows.push(['frame_smoothness_initial', fmt(f.frame_smoothness_initial, 3)], ['frame_smoothness_final', fmt(f.frame_smoothness_final, 3)]);
    }
    fillStats($('volume-stats'), rows);
    $('volume-legend-min').textContent = fmt(v.min, 3);
    $('volume-legend-max').textContent = fmt(v.max, 3);
  },
};
$('volume-legend-bar').style.background = `linear-gradient(to right, ${DENSITY_STOPS.map(([t, c]) => `rgb(${c.join(',')}) ${100 * t}%`).join(', ')})`;
acceptFiles($('panel-volume'), $('volume-file'), (b, n) => volumeTab.open(b, n));
$('volume-axis').addEventListener('change', () => volumeTab.setAxis());
$('volume-slice').addEventListener('input', () => volumeTab.draw());
$('volume-run').addEventListener('click', () => volumeTab.run());
$('volume-download-json').addEventListener('click', () => {
  const f = volumeTab.fit;
  if (f) download(f.spline_json, baseName(volumeTab.volume.name) + '.spline.json', 'application/json');
});

// ---- lens tab ---------------------------------------------------------------------------------
const lensTab = {
  view: null,
  key: null,          // worker-side image key
  generation: 0,      // worker generation the image was sent to (a restarted worker lost it)
  bytes: null, name: null,
  roi: null,
  calibrated: null,   // {magnification, grid, height}: reuse h0 while only the ROI or α changes
  pending: false, running: false,
  lastFrame: 0, frameMs: [],  // intervals between live results shown (the frame time while dragging)
  frameLog: [],               // per live result: {ms (interval or 0), ms_total, ms_worker}; read by the e2e test
  result: null,

  options() {
    return {
      method: document.querySelector('input[name="lens-method"]:checked').value,
      alpha: Number($('lens-alpha').value),
      magnification: Number($('lens-magnification').value),
      grid: Number($('lens-grid').value),
    };
  },

  async open(bytes, name) {
    clearError();
    const key = `${name}#${Date.now()}`;
    const r = await runJob('setImage', { key, bytes: bytes.slice(), name });
    if (!r.ok) { if (r.message !== 'cancelled') showError(r.message); return; }
    Object.assign(this, { key, bytes, name, generation: jobs.generation, calibrated: null, frameMs: [], reuses: 0 });
    const { width, height } = r.image;
    this.roi = { cx: width / 2, cy: height / 2, r: Math.max(4, Math.round(Math.min(width, height) / 6)) };
    this.view.setImage(r.image);
    this.view.setRoi(this.roi);
    $('lens-hint').hidden = true;
    this.update(false);
  },

  /// Re-runs the job with the current controls; while a run is in flight only the latest request
  /// is kept, so dragging never queues stale work.
  update(live) {
    if (!this.key) return;
    this.live = live;
    if (this.running) { this.pending = true; return; }
    this.runOnce();
  },

  async runOnce() {
    this.running = true;
    this.pending = false;
    try {
      if (this.generation !== jobs.generation) {  // the worker was restarted by a cancel
        const r = await runJob('setImage', { key: this.key, bytes: this.bytes.slice(), name: this.name }, { quiet: true });
        if (!r.ok) { showError(r.message); return; }
        this.generation = jobs.generation;
      }
      const o = this.options();
      // While dragging, the core may answer a move by translating the last solved lens (mode
      // 'live'); the release runs the full job, so what stays on screen is a full result.
      const options = { ...o, render: false, ...(this.live ? { mode: 'live' } : {}) };
      const c = this.calibrated;
      if (o.method === 'metric' && c && c.magnification === o.magnification && c.grid === o.grid) options.height = c.height;
      const roi = { ...this.roi };
      // The same request as the one on screen (e.g. the release after a drag) is not re-run.
      const request = JSON.stringify([this.key, this.generation, roi, options]);
      if (request === this.lastRequest && this.lastRun) {
        if (!this.live) { this.showTiming(this.lastRun); this.showStats(this.lastRun.stats, o.method); }
        return;
      }
      const r = await runJob('lens', { key: this.key, rois: [{ shape: 'circle', values: [roi.cx, roi.cy, roi.r] }], options }, { quiet: this.live });
      if (!r.ok) { this.lastRequest = null; if (r.message !== 'cancelled') showError(r.message); return; }
      this.lastRequest = request;
      this.lastRun = r;
      if (o.method === 'metric' && !options.height) this.calibrated = { magnification: o.magnification, grid: o.grid, height: r.stats.height };
      // Drawn at the next animation frame (onFrame below), while the worker already computes the
      // next request: the frame time is max(core, drawing), not their sum.
      this.view.setMesh(r.positions, r.texture, r.triangles);
      this.shownLive = this.live ? r : null;
      this.result = { image: this.name, roi, options: { ...o, height: r.stats.height || undefined }, stats: r.stats };
      // While dragging, the text readouts are refreshed at most every 200 ms (layout is not free).
      const now = performance.now();
      if (!this.live || now - (this.lastText ?? 0) > 200) {
        this.lastText = now;
        this.showTiming(r);
        this.showStats(r.stats, o.method);
      }
      $('lens-download-png').disabled = $('lens-download-json').disabled = false;
    } finally {
      this.running = false;
      if (this.pending) this.runOnce();
    }
  },

  /// After every drawn frame: the interval between frames that showed a new live result.
  onFrame() {
    const r = this.shownLive;
    this.shownLive = null;
    if (!r) { if (!this.live) this.lastFrame = 0; return; }
    const now = performance.now();
    const interval = this.lastFrame ? now - this.lastFrame : 0;
    if (interval) { this.frameMs.push(interval); if (this.frameMs.length > 60) this.frameMs.shift(); }
    this.frameLog.push({ ms: interval, ms_total: r.stats.ms_total, ms_worker: r.ms_worker, translated: r.stats.translated });
    if (this.frameLog.length > 1000) this.frameLog.shift();
    this.lastFrame = now;
  },

  /// The readout over the image: the core's ms_total of the last run, the worker round trip and,
  /// while dragging or sliding, the median frame time of the recent live updates.
  showTiming(r) {
    const median = (a) => { const b = [...a].sort((x, y) => x - y); return b.length ? b[b.length >> 1] : 0; };
    let text = `last run ${r.stats.ms_total.toFixed(1)} ms (worker ${r.ms_worker.toFixed(1)} ms)`;
    if (r.stats.translated) text += ' · lens moved, not re-solved (live)';
    else if (r.session) text += r.session.mesh_reuses > (this.reuses ?? 0) ? ' · factorization reused' : '';
    this.reuses = r.session ? r.session.mesh_reuses : 0;
    if (this.frameMs.length) { const m = median(this.frameMs); text += ` · frame ${m.toFixed(1)} ms (${(1000 / m).toFixed(0)} fps)`; }
    $('lens-timing').textContent = text;
  },

  showStats(s, method) {
    const median = (a) => { const b = [...a].sort((x, y) => x - y); return b.length ? b[b.length >> 1] : 0; };
    const rows = [
      ['method', method], ['magnification_center', fmt(s.magnification_center)],
      ['distortion_sum', fmt(s.distortion_sum)], ['distortion_max', fmt(s.distortion_max)],
      ['distortion_max_focus', fmt(s.distortion_max_focus)],
      ['flipped_triangles', s.flipped_triangles], ['iterations', s.iterations], ['converged', s.converged ? 'yes' : 'no'],
      ['ms_per_iteration', fmt(s.ms_per_iteration, 3)], ['ms_total', fmt(s.ms_total, 3)],
      ['ms_calibration', fmt(s.ms_calibration, 3)], ['ms_factorize', fmt(s.ms_factorize, 3)],
      ['height', fmt(s.height)], ['baseline_parameter', fmt(s.baseline_parameter)],
      ['vertices', s.vertices], ['triangles', s.triangles],
    ];
    if (this.frameMs.length) rows.push(['live_frame_ms', fmt(median(this.frameMs), 3)], ['live_fps', fmt(1000 / median(this.frameMs), 3)]);
    fillStats($('lens-stats'), rows);
  },
};
try {
  lensTab.view = new LensView({ canvas: $('lens-canvas'), ring: $('lens-ring'), overlay: $('lens-overlay') }, (roi, live) => { lensTab.roi = roi; lensTab.update(live); });
  lensTab.view.onFrame = () => lensTab.onFrame();
} catch (e) {
  showError(e.message);
}
acceptFiles($('panel-lens'), $('lens-file'), (b, n) => lensTab.open(b, n));
for (const id of ['lens-alpha', 'lens-magnification']) {
  $(id).addEventListener('input', () => { $(id + '-value').textContent = $(id).value; lensTab.update(true); });
  $(id).addEventListener('change', () => lensTab.update(false));
}
$('lens-grid').addEventListener('change', () => lensTab.update(false));
for (const radio of document.querySelectorAll('input[name="lens-method"]')) radio.addEventListener('change', () => lensTab.update(false));
$('lens-download-json').addEventListener('click', () => {
  download(JSON.stringify(lensTab.result, null, 2) + '\n', lensTab.name.replace(/\.[^.]*$/, '') + '.lens.json', 'application/json');
});
$('lens-download-png').addEventListener('click', async () => {
  if (lensTab.running) return;
  const o = lensTab.options();
  const c = lensTab.calibrated;
  const options = { ...o };
  if (o.method === 'metric' && c && c.magnification === o.magnification && c.grid === o.grid) options.height = c.height;
  const { cx, cy, r } = lensTab.roi;
  const result = await runJob('lensPng', { key: lensTab.key, rois: [{ shape: 'circle', values: [cx, cy, r] }], options });
  if (!result.ok) { if (result.message !== 'cancelled') showError(result.message); return; }
  download(result.bytes, lensTab.name.replace(/\.[^.]*$/, '') + `.${o.method}.png`, 'image/png');
});

// ---- samples and start ------------------------------------------------------------------------
fetch('samples/index.json').then((r) => (r.ok ? r.json() : [])).then((list) => {
  samplesMenu($('mesh-samples'), 'meshes', list, (b, n) => meshTab.open(b, n));
  samplesMenu($('lens-samples'), 'images', list, (b, n) => lensTab.open(b, n));
  samplesMenu($('volume-samples'), 'volumes', list, (b, n) => volumeTab.open(b, n));
  $('volume-samples').hidden = !list.some((s) => s.kind === 'volumes');
}).catch(() => {});
selectTab(tabs.includes(location.hash.slice(1)) ? location.hash.slice(1) : 'mesh');

// Hooks for the end-to-end tests and the console (read-only use).
window.volspline = { jobs, meshTab, lensTab, volumeTab, showError };
