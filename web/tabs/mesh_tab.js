// SPDX-License-Identifier: MIT
// The Mesh tab: open a mesh (its facts), run a spline job on it, show the result in the 3D view
// with a cut, the stats and the downloads. Another job on the same mesh adds a run button with
// meshTab.addRun({button, job, options, render, reset, anyGenus}): its result goes to `render`
// (the hook a new job's view and stats use), `reset` clears what render showed when another mesh
// or result replaces it; the tab handles busy state, errors and cancellation. A run marked
// anyGenus (gpc) is what "Run mesh2spline" starts on a solid of genus ≥ 1, which mesh2spline
// refuses (it maps a solid to one cuboid).
import { $, jobs, runJob, showError, clearError, download, acceptFiles, fillStats, fmt, baseName } from '../ui.js';
import { MeshView, QUALITY_GRADIENT } from '../mesh_view.js';

export const meshTab = {
  view: null,
  info: null,        // meshInfo result of the open mesh (without its arrays)
  bytes: null, name: null,
  result: null,      // the last mesh2spline result
  runs: [],          // the jobs added by addRun: {button, job, reset, anyGenus, start}
  lastRun: null,     // {job, options, result} of the last addRun job shown
  cutRunning: false, cutPending: false,

  async open(bytes, name) {
    clearError();
    const r = await runJob('meshInfo', { bytes: bytes.slice(), name });
    if (!r.ok) { if (r.message !== 'cancelled') showError(r.message); return; }
    const { positions, triangles, ok, ms_worker, ...facts } = r;
    Object.assign(this, { info: { file: name, ...facts }, bytes, name });
    this.clearResults();
    $('mesh-show-input').checked = true;
    if (this.view) this.view.visible.input = true;
    this.view?.setMesh(positions, triangles, r.bbox_min, r.bbox_max);
    this.showInfo();
    this.updateButtons();
    $('mesh-download-stats').disabled = false;
    const fallback = this.anyGenusRun();
    this.notice(this.info.genus > 0 && fallback
      ? `${name} has genus ${this.info.genus}: mesh2spline needs genus 0 (one cuboid), so Run mesh2spline builds the GPC domain instead`
      : '');
  },

  /// Enables each run button whose job the core offers, once a mesh is open.
  updateButtons() {
    $('mesh-run').disabled = !this.bytes || !jobs.available?.includes('mesh2spline');
    for (const run of this.runs) run.button.disabled = !this.bytes || !jobs.available?.includes(run.job);
  },

  /// The run that takes a solid of any genus, if the core offers it.
  anyGenusRun() { return this.runs.find((run) => run.anyGenus && jobs.available?.includes(run.job)) ?? null; },

  /// Shows `text` in the tab's notice line (a remark, not an error); '' hides it.
  notice(text) {
    $('mesh-notice').textContent = text;
    $('mesh-notice').hidden = !text;
  },

  /// Forgets the shown results of every job (the view's layers are replaced by the caller).
  clearResults() {
    this.result = null;
    this.lastRun = null;
    for (const k of ['json', 'glb', 'vtu']) $('mesh-download-' + k).disabled = true;
    $('mesh-legend').hidden = true;
    for (const run of this.runs) run.reset?.();
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
    const fallback = this.anyGenusRun();
    if (this.info?.genus > 0 && fallback) {
      this.notice(`${this.name} has genus ${this.info.genus}: mesh2spline maps a solid to one cuboid and needs genus 0, ` +
                  `so its GPC domain (any genus) is built instead`);
      return fallback.start();
    }
    clearError();
    $('mesh-run').disabled = true;
    const options = this.options();
    const r = await runJob('mesh2spline', { bytes: this.bytes.slice(), name: this.name, options });
    $('mesh-run').disabled = false;
    if (!r.ok) { if (r.message !== 'cancelled') showError(r.message); return; }
    this.clearResults();
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

  /// Adds a job that runs on the open mesh: `button` (an element) starts it with `options()`,
  /// `render(result)` shows its result, `reset()` (optional) clears it when another mesh or result
  /// replaces it; anyGenus: this job is run instead of mesh2spline on a solid of genus ≥ 1. The
  /// job gets {bytes, name, options} like mesh2spline; its result's `stats` are the stats download.
  /// Returns the start function (what a click does): resolves when the job has finished.
  addRun({ button, job, options, render, reset = null, anyGenus = false }) {
    const start = async () => {
      if (!this.bytes || jobs.busy) return;
      clearError();
      button.disabled = true;
      const opts = options();
      const r = await runJob(job, { bytes: this.bytes.slice(), name: this.name, options: opts });
      button.disabled = false;
      if (!r.ok) { if (r.message !== 'cancelled') showError(r.message); return; }
      this.clearResults();
      this.lastRun = { job, options: opts, result: r };
      // The input mesh would hide the result: shown again by its checkbox.
      $('mesh-show-input').checked = false;
      if (this.view) this.view.visible.input = false;
      render(r);
    };
    this.runs.push({ button, job, reset, anyGenus, start });
    button.addEventListener('click', start);
    this.updateButtons();
    return start;
  },

  statsJson() {
    if (this.lastRun) return { job: this.lastRun.job, ...this.lastRun.result.stats, options: this.lastRun.options };
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
for (const layer of ['input', 'wireframe', 'boundary', 'lines', 'control', 'cut', 'cuboids', 'poly_edges']) {
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
  const suffix = meshTab.lastRun ? `.${meshTab.lastRun.job}.stats.json` : meshTab.result ? '.stats.json' : '.info.json';
  download(JSON.stringify(meshTab.statsJson(), null, 2) + '\n', baseName(meshTab.name) + suffix, 'application/json');
});

