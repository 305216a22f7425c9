// SPDX-License-Identifier: MIT
// The page: tabs, file picking and drag-and-drop, the samples menu, the job bar (progress and
// cancel), the Mesh and Lens tabs, error display and downloads. The core runs in the worker;
// this file never sees a C++ type, only {ok, ...} objects and typed arrays.
import { JobClient } from './job_client.js';
import { MeshView } from './mesh_view.js';
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
jobs.onState((state) => { $('job-cancel').disabled = state !== 'busy'; });
$('job-cancel').addEventListener('click', () => jobs.cancel());

/// Runs a job with the job bar; long-running or not, the UI stays responsive (the worker computes).
async function runJob(job, args, { quiet = false, transfer = [] } = {}) {
  if (!quiet) setProgress(job + '…', 0);
  const result = await jobs.run(job, args, { transfer, onProgress: (stage, f) => setProgress(stage, f) });
  if (!quiet || !result.ok) setProgress(result.ok ? `${job}: done (${result.ms_worker.toFixed(0)} ms)` : `${job}: ${result.message === 'cancelled' ? 'cancelled' : 'failed'}`, result.ok ? 1 : 0);
  return result;
}

jobs.ready().then(({ version, jobs: available }) => {
  $('core-version').textContent = 'core ' + version;
  setProgress('ready', 0);
  if (available.includes('mesh2spline')) { $('mesh-run').disabled = false; $('mesh-run').title = ''; }
}, (e) => { setProgress('core failed to load', 0); showError(e.message); });

// ---- tabs -------------------------------------------------------------------------------------
const tabs = ['mesh', 'lens', 'volume'];
function selectTab(name) {
  for (const t of tabs) {
    $('tab-' + t).setAttribute('aria-selected', String(t === name));
    $('panel-' + t).hidden = t !== name;
  }
  if (name === 'mesh') meshTab.view?.draw();
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
const meshTab = {
  view: null,
  info: null,
  async open(bytes, name) {
    clearError();
    const r = await runJob('meshInfo', { bytes, name }, { transfer: [bytes.buffer] });
    if (!r.ok) { if (r.message !== 'cancelled') showError(r.message); return; }
    this.info = { name, ...r };
    this.view?.setMesh(r.positions, r.triangles, r.bbox_min, r.bbox_max);
    const bbox = (v) => v.map((x) => fmt(x, 3)).join(', ');
    fillStats($('mesh-stats'), [
      ['file', name], ['vertices', r.vertices], ['faces', r.faces], ['edges', r.edges],
      ['closed', r.closed ? 'yes' : 'no'], ['manifold', r.manifold ? 'yes' : 'no'],
      ['components', r.components], ['boundary_loops', r.boundary_loops],
      ['genus', r.genus === null ? 'undefined' : r.genus], ['euler_characteristic', r.euler_characteristic],
      ['consistently_oriented', r.consistently_oriented ? 'yes' : 'no'], ['degenerate_faces', r.degenerate_faces],
      ['signed_volume', fmt(r.signed_volume)], ['bbox_min', bbox(r.bbox_min)], ['bbox_max', bbox(r.bbox_max)],
    ]);
    $('mesh-download-json').disabled = false;
  },
};
try {
  meshTab.view = new MeshView($('mesh-canvas'));
} catch (e) {
  showError(e.message);
}
acceptFiles($('panel-mesh'), $('mesh-file'), (b, n) => meshTab.open(b, n));
$('mesh-wireframe').addEventListener('change', (e) => { if (meshTab.view) { meshTab.view.wireframe = e.target.checked; meshTab.view.draw(); } });
$('mesh-download-json').addEventListener('click', () => {
  const { positions, triangles, ok, ms_worker, ...facts } = meshTab.info;
  download(JSON.stringify(facts, null, 2) + '\n', facts.name.replace(/\.[^.]*$/, '') + '.info.json', 'application/json');
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
      const options = { ...o, render: false };
      const c = this.calibrated;
      if (o.method === 'metric' && c && c.magnification === o.magnification && c.grid === o.grid) options.height = c.height;
      const roi = { ...this.roi };
      const r = await runJob('lens', { key: this.key, rois: [{ shape: 'circle', values: [roi.cx, roi.cy, roi.r] }], options }, { quiet: this.live });
      if (!r.ok) { if (r.message !== 'cancelled') showError(r.message); return; }
      if (o.method === 'metric' && !options.height) this.calibrated = { magnification: o.magnification, grid: o.grid, height: r.stats.height };
      this.view.setMesh(r.positions, r.texture, r.triangles);
      const now = performance.now();
      const interval = this.live && this.lastFrame ? now - this.lastFrame : 0;
      if (interval) { this.frameMs.push(interval); if (this.frameMs.length > 60) this.frameMs.shift(); }
      if (this.live) { this.frameLog.push({ ms: interval, ms_total: r.stats.ms_total, ms_worker: r.ms_worker }); if (this.frameLog.length > 1000) this.frameLog.shift(); }
      this.lastFrame = now;
      this.showTiming(r);
      this.result = { image: this.name, roi, options: { ...o, height: r.stats.height || undefined }, stats: r.stats };
      this.showStats(r.stats, o.method);
      $('lens-download-png').disabled = $('lens-download-json').disabled = false;
    } finally {
      this.running = false;
      if (this.pending) this.runOnce();
      else if (!this.live) this.lastFrame = 0;
    }
  },

  /// The readout over the image: the core's ms_total of the last run, the worker round trip and,
  /// while dragging or sliding, the median frame time of the recent live updates.
  showTiming(r) {
    const median = (a) => { const b = [...a].sort((x, y) => x - y); return b.length ? b[b.length >> 1] : 0; };
    let text = `last run ${r.stats.ms_total.toFixed(1)} ms (worker ${r.ms_worker.toFixed(1)} ms)`;
    if (r.session) text += r.session.mesh_reuses > (this.reuses ?? 0) ? ' · factorization reused' : '';
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
  lensTab.view = new LensView($('lens-canvas'), $('lens-overlay'), (roi, live) => { lensTab.roi = roi; lensTab.update(live); });
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
}).catch(() => {});
selectTab(tabs.includes(location.hash.slice(1)) ? location.hash.slice(1) : 'mesh');

// Hooks for the end-to-end tests and the console (read-only use).
window.volspline = { jobs, meshTab, lensTab, showError };
