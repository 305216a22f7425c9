// SPDX-License-Identifier: MIT
// The Mesh tab: open a mesh (its facts), run a spline job on it, show the result in the 3D view
// with a cut, the stats and the downloads. Another job on the same mesh adds a run button with
// meshTab.addRun({button, job, options, render, reset}): its result goes to `render` (the hook a
// new job's view and stats use), `reset` clears what render showed when another mesh or result
// replaces it; the tab handles busy state, errors and cancellation. mesh2spline takes a solid of
// any genus: genus 0 gives one cuboid, genus ≥ 1 a spline over its GPC domain (result.domain
// 'gpc'), whose boundary is coloured by cuboid.
import { $, jobs, runJob, showError, clearError, download, acceptFiles, fillStats, fmt, baseName, markStale } from '../ui.js';
import { MeshView, QUALITY_GRADIENT } from '../mesh_view.js';
import { splineLattice } from '../spline_json.js';

// The splineQuality lattice (points per axis) of the histogram and the folded points.
const QUALITY_LATTICE = 24;
// The CLI's surface error target (fraction of the bbox diagonal): the verdict's Hausdorff target.
const SURFACE_TARGET = 0.005;
const DISTANCE_GRADIENT = 'linear-gradient(to right, rgb(224,230,242) 0%, rgb(250,184,64) 50%, rgb(204,26,26) 100%)';
// The cut as drawn: its scaled Jacobian, with every point inside a cell the det J certificate
// does not certify (stats.uncertified_cells: cuboid and uvw box) shown as a fold (−1, red), so
// the cut, the stats and the VTU's scaled_jacobian_min tell the same cells. Sets cut.display and
// cut.uncertified_points.
function markUncertified(cut, stats) {
  const cells = stats?.uncertified_cells ?? [];
  const display = Float32Array.from(cut.scaled_jacobian);
  let marked = 0;
  if (cells.length && cut.uvw) {
    for (let k = 0; k < display.length; k++) {
      const cuboid = cut.cuboid ? cut.cuboid[k] : 0;
      const inside = cells.some((c) => c.cuboid === cuboid && [0, 1, 2].every((a) => {
        const tol = 1e-6 * Math.max(1, Math.abs(c.uvw_max[a]));
        return cut.uvw[3 * k + a] >= c.uvw_min[a] - tol && cut.uvw[3 * k + a] <= c.uvw_max[a] + tol;
      }));
      if (inside) { display[k] = -1; marked++; }
    }
  }
  cut.display = display;
  cut.uncertified_points = marked;
}

// The det J certificate's stats rows (both kinds of spline).
function certificateRows(s) {
  return [['jacobian_certified_fraction', fmt(s.jacobian_certified_fraction, 6)], ['det_j_lower_bound_rel', fmt(s.det_j_lower_bound_rel, 3)],
    ['certificate_cells', s.certificate_cells], ['uncertified_cells', (s.uncertified_cells ?? []).length]];
}

// The cut's colours (mesh_shaders.js quality()) for q in (0, 1], as CSS.
function qualityColour(q) {
  const stops = [[0, [0.95, 0.45, 0.1]], [0.33, [0.98, 0.85, 0.2]], [0.67, [0.3, 0.75, 0.35]], [1, [0.2, 0.4, 0.85]]];
  let k = 0;
  while (k < stops.length - 2 && q > stops[k + 1][0]) k++;
  const [t0, c0] = stops[k], [t1, c1] = stops[k + 1];
  const f = Math.max(0, Math.min(1, (q - t0) / (t1 - t0)));
  return `rgb(${c0.map((c, i) => Math.round(255 * (c + f * (c1[i] - c)))).join(',')})`;
}

export const meshTab = {
  view: null,
  info: null,        // meshInfo result of the open mesh (without its arrays)
  defaultLevels: '4',  // the levels setting's default for the open mesh's genus ('' = auto)
  bytes: null, name: null,
  result: null,      // the last mesh2spline result
  runs: [],          // the jobs added by addRun: {button, job, reset, start}
  lastRun: null,     // {job, options, result} of the last addRun job shown
  cutRunning: false, cutPending: false,

  async open(bytes, name) {
    clearError();
    const r = await runJob('meshInfo', { bytes: bytes.slice(), name });
    if (!r.ok) { if (r.message !== 'cancelled') showError(r.message); return; }
    const { positions, triangles, ok, ms_worker, ...facts } = r;
    Object.assign(this, { info: { file: name, ...facts }, bytes, name });
    // The levels follow the CLI's default for the genus (4; genus > 0: auto, the GPC job's own
    // default) unless they were changed from the default shown.
    const levels = this.info.genus > 0 ? '' : '4';
    if ($('mesh-levels').value === this.defaultLevels) $('mesh-levels').value = levels;
    this.defaultLevels = levels;
    this.clearResults();
    $('mesh-show-input').checked = true;
    if (this.view) this.view.visible.input = true;
    this.view?.setMesh(positions, triangles, r.bbox_min, r.bbox_max);
    this.showInfo();
    this.updateButtons();
    $('mesh-download-stats').disabled = false;
    this.notice(this.info.genus > 0
      ? `${name} has genus ${this.info.genus}: mesh2spline fits one spline over its generalized poly-cube (several cuboids, each in its own colour)`
      : '');
  },

  /// Enables each run button whose job the core offers, once a mesh is open.
  updateButtons() {
    $('mesh-run').disabled = !this.bytes || !jobs.available?.includes('mesh2spline');
    for (const run of this.runs) run.button.disabled = !this.bytes || !jobs.available?.includes(run.job);
  },

  /// Shows `text` in the tab's notice line (a remark, not an error); '' hides it.
  notice(text) {
    $('mesh-notice').textContent = text;
    $('mesh-notice').hidden = !text;
  },

  /// After a cancelled or failed run of `job` with `options`: if a result is shown, it is marked
  /// as the previous run's.
  markStale(job, options, why) {
    const shown = this.lastRun ?? (this.result && { job: 'mesh2spline', options: this.result.options });
    if (!shown) return;
    const levels = (o) => ('max_levels' in o ? `, levels ${o.max_levels}` : '');
    markStale([$('mesh-canvas').parentElement, $('mesh-stats'), $('mesh-verdict')], $('mesh-stale'),
              `${job}${levels(options)} ${why}: the view and stats show the previous result (${shown.job}${levels(shown.options)})`);
  },

  /// Forgets the shown results of every job (the view's layers are replaced by the caller).
  clearResults() {
    markStale([$('mesh-canvas').parentElement, $('mesh-stats'), $('mesh-verdict')], $('mesh-stale'), '');
    this.result = null;
    this.lastRun = null;
    $('mesh-verdict').hidden = true;
    for (const id of ['mesh-histogram', 'mesh-distance-legend']) $(id).hidden = true;
    $('mesh-probe').textContent = '';
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
    const levels = $('mesh-levels').value;
    return {
      // auto ('') leaves the levels to the job's default.
      ...(levels === '' ? {} : { max_levels: Number(levels) }), fit: $('mesh-fit').value,
      // The CLI's targets, sent explicitly: the verdict line compares the result with them. The
      // surface target only for genus 0: the GPC job refines by rms alone unless asked (as the CLI).
      max_rms_rel: 0.002, ...(this.info?.genus > 0 ? {} : { max_surface_error_rel: SURFACE_TARGET }),
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
    if (!r.ok) {
      if (r.message !== 'cancelled') showError(r.message);
      this.markStale('mesh2spline', options, r.message === 'cancelled' ? 'was cancelled' : 'failed');
      return;
    }
    this.clearResults();
    this.result = { ...r, options };
    if (r.cut) markUncertified(r.cut, r.stats);
    // A GPC spline's JSON has no single-patch anchors (no lattice); its control points carry
    // their anchors in control_uvw.
    const gpc = r.domain === 'gpc';
    this.view?.setSpline(r, r.spline_json && !gpc ? splineLattice(r.spline_json) : null);
    this.showVerdict();
    await this.runQuality();
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

  /// The quality views of the shown spline (the splineQuality job): the scaled-Jacobian histogram,
  /// the folded points and the boundary's distance to the mesh.
  async runQuality() {
    const result = this.result;
    if (!result?.spline_json || !jobs.available?.includes('splineQuality')) return;
    // A GPC spline's boundary keeps its cuboid colours: no distance colours asked for.
    const bytes = result.domain === 'gpc' ? null : this.bytes.slice();
    const r = await runJob('splineQuality', { json: result.spline_json.slice(), bytes, name: this.name, options: { lattice: QUALITY_LATTICE } });
    if (this.cutPending) this.updateCut();  // a cut asked for while this ran
    if (this.result !== result) return;  // another run or mesh replaced it meanwhile
    if (!r.ok) { if (r.message !== 'cancelled') showError(r.message); return; }
    const target = result.options.max_surface_error_rel ?? SURFACE_TARGET;
    result.quality = { ...r, target };
    this.applyQuality();
    this.showHistogram();
    this.showVerdict();
    const pct = (x) => `${fmt(100 * x, 2)}`;
    $('mesh-distance-bar').style.background = DISTANCE_GRADIENT;
    $('mesh-distance-mid').textContent = pct(target / 2);
    $('mesh-distance-max').textContent = '≥ ' + pct(target);
    $('mesh-distance-legend').hidden = !$('mesh-show-distance').checked || !r.boundary_distance_rel;
  },

  /// Hands the quality views to the 3D view, the distance colours as the checkbox says.
  applyQuality() {
    const q = this.result?.quality;
    if (!q || !this.view) return;
    const colour = $('mesh-show-distance').checked && q.boundary_distance_rel;
    this.view.setQuality({ folded: q.folded, boundaryDistance: colour ? q.boundary_distance_rel.map((d) => d / q.target) : null });
    $('mesh-distance-legend').hidden = !colour;
  },

  /// The histogram of the scaled Jacobian over the lattice: one bar per bin over [−1, 1], bars
  /// at or below 0 red, the others in the cut's colours; heights on a square-root scale so a few
  /// folded points still show.
  showHistogram() {
    const q = this.result.quality;
    const svg = $('mesh-histogram-svg');
    const ns = 'http://www.w3.org/2000/svg';
    const max = Math.max(...q.counts, 1);
    const w = 200 / q.bins;
    const bars = Array.from(q.counts, (count, i) => {
      const centre = -1 + (2 * (i + 0.5)) / q.bins;
      const h = count ? Math.max(1.5, 66 * Math.sqrt(count / max)) : 0;
      const rect = document.createElementNS(ns, 'rect');
      rect.setAttribute('x', String(i * w + 0.5)); rect.setAttribute('width', String(w - 1));
      rect.setAttribute('y', String(68 - h)); rect.setAttribute('height', String(h));
      rect.setAttribute('fill', centre <= 0 ? 'rgb(217,26,26)' : qualityColour(centre));
      const title = document.createElementNS(ns, 'title');
      title.textContent = `${fmt(-1 + (2 * i) / q.bins, 2)} to ${fmt(-1 + (2 * (i + 1)) / q.bins, 2)}: ${count} points`;
      rect.append(title);
      return rect;
    });
    const zero = document.createElementNS(ns, 'line');
    for (const [k, v] of [['x1', 100], ['x2', 100], ['y1', 0], ['y2', 70]]) zero.setAttribute(k, String(v));
    zero.setAttribute('stroke', '#475569'); zero.setAttribute('stroke-dasharray', '2 2');
    svg.replaceChildren(...bars, zero);
    const folded = q.folded.length / 3;
    const where = q.cuboids > 1 ? `${QUALITY_LATTICE}³ points in each of ${q.cuboids} cuboids` : `${QUALITY_LATTICE}³ points`;
    $('mesh-histogram-caption').textContent = `scaled Jacobian at ${where}: ${folded ? `${folded} folded (≤ 0)` : 'none folded'}, min ${fmt(q.min_scaled_jacobian, 3)}`;
    $('mesh-histogram').hidden = false;
  },

  /// Shows what is under the pointer in the 3D view: the cut's scaled Jacobian, the boundary's
  /// distance to the mesh, or the position.
  probe(clientX, clientY) {
    const hit = this.view?.pick(clientX, clientY);
    const xyz = hit ? hit.xyz.map((x) => fmt(x, 4)).join(', ') : '';
    let text = '';
    if (hit?.layer === 'cut' && hit.scalar !== null) text = `cut: scaled Jacobian ${fmt(hit.scalar, 3)} at (${xyz})`;
    else if (hit?.layer === 'boundary' && hit.scalar !== null && this.result?.quality) text = `boundary: ${fmt(100 * hit.scalar * this.result.quality.target, 3)} % of the diagonal from the mesh at (${xyz})`;
    else if (hit) text = `${hit.layer === 'input' ? 'mesh' : hit.layer} at (${xyz})`;
    $('mesh-probe').textContent = text;
  },

  /// The result at a glance: folds (det J ≤ 0 somewhere), a poor fit (beyond the RMS or surface
  /// error target), or a fit within target.
  showVerdict() {
    const s = this.result.stats, o = this.result.options, q = this.result.quality, cut = this.result.cut;
    const pct = (x) => `${fmt(100 * x, 2)} %`;
    const surface = o.max_surface_error_rel ?? SURFACE_TARGET;
    const fit = `RMS distance ${pct(s.rms_rel)} of the diagonal (target ${pct(o.max_rms_rel)}), Hausdorff ${pct(s.hausdorff_rel)} (target ${pct(surface)})`;
    const poor = s.rms_rel > o.max_rms_rel || s.hausdorff_rel > surface;
    // Folds seen anywhere: the job's Gauss points, the quality lattice, or the cut shown.
    const where = [];
    if (s.negative_jacobian_fraction > 0 || s.min_scaled_jacobian <= 0) where.push(`${pct(s.negative_jacobian_fraction)} of the Gauss points`);
    if (s.lattice_negative_fraction > 0) where.push(`${pct(s.lattice_negative_fraction)} of the ${s.lattice_samples} lattice points`);
    if (q && q.folded.length) where.push(`${q.folded.length / 3} of ${q.samples} lattice points`);
    if (cut && cut.min_scaled_jacobian <= 0) where.push(`the cut (min scaled Jacobian ${fmt(cut.min_scaled_jacobian, 3)})`);
    const minQ = Math.min(s.min_scaled_jacobian, q ? q.min_scaled_jacobian : 1);
    // The headline is the det J certificate: every cell certified, or the cells it does not.
    const uncertified = s.uncertified_cells ?? [];
    let certified = '';
    if (Number.isFinite(s.jacobian_certified_fraction)) {
      if (!uncertified.length) {
        certified = `; certified fold-free (all ${s.certificate_cells} cells)`;
      } else {
        const box = (c) => `cuboid ${c.cuboid} cell ${c.cell} uvw [${c.uvw_min.map((x) => fmt(x, 3)).join(', ')}]–[${c.uvw_max.map((x) => fmt(x, 3)).join(', ')}] (${c.status})`;
        const more = uncertified.length > 3 ? ` and ${uncertified.length - 3} more` : '';
        certified = `; ${uncertified.length} of ${s.certificate_cells} cells not certified fold-free: ${uncertified.slice(0, 3).map(box).join('; ')}${more}`;
        const negative = uncertified.filter((c) => c.status === 'negative').length;
        if (negative) where.push(`${negative} cells (proven by the certificate)`);
        if (cut?.uncertified_points) certified += `. The cut draws its ${cut.uncertified_points} points in those cells red`;
      }
    }
    let kind, text;
    if (where.length) {
      kind = 'folds';
      text = `Folds: det J ≤ 0 at ${where.join(', ')}${certified}. ${poor ? 'Poor fit too' : 'Fit within target'}: ${fit}.`;
    } else if (poor) {
      kind = 'poor';
      text = `Poor fit: ${fit}; no folds (min scaled Jacobian ${fmt(minQ, 3)})${certified}. More levels may reach the target.`;
    } else {
      kind = 'good';
      text = `Fit within target: ${fit}; no folds (min scaled Jacobian ${fmt(minQ, 3)})${certified}.`;
    }
    const v = $('mesh-verdict');
    v.className = 'verdict ' + kind;
    v.dataset.verdict = kind;
    v.textContent = text;
    v.hidden = false;
  },

  showStats() {
    const s = this.result.stats, i = this.info;
    if (this.result.domain === 'gpc') {
      fillStats($('mesh-stats'), [
        ['file', i.file], ['vertices', i.vertices], ['faces', i.faces], ['genus', s.genus],
        ['cuboids', s.cuboids], ['t_shapes', s.t_shapes], ['ill_points', s.ill_points],
        ['interfaces', s.interfaces], ['continued_interfaces', s.continued_interfaces],
        ['rms_rel', fmt(s.rms_rel, 3)], ['max_rel', fmt(s.max_rel, 3)],
        ['hausdorff_rel', fmt(s.hausdorff_rel, 3)], ['rms_geo_rel', fmt(s.rms_geo_rel, 3)],
        ['control_points', s.control_points], ['levels', s.levels],
        ...certificateRows(s),
        ['min_scaled_jacobian', fmt(s.min_scaled_jacobian, 3)], ['negative_jacobian_fraction', fmt(s.negative_jacobian_fraction, 3)],
        ['lattice_negative_fraction', fmt(s.lattice_negative_fraction, 3)],
        ['semi_standard_max_error', fmt(s.semi_standard_max_error, 3)],
        ['interface_gap_rel', fmt(s.interface_gap_rel, 3)], ['interface_normal_jump_deg', fmt(s.interface_normal_jump_deg, 3)],
        ['flipped_triangles', s.flipped_triangles], ['grid_inverted_hexes', s.grid_inverted_hexes],
        ['grid_min_scaled_jacobian', fmt(s.grid_min_scaled_jacobian, 3)], ['samples', s.samples],
        ['untangled_control_points', s.untangled_control_points],
        ['untangle_surface_shift_rel', fmt(s.untangle_surface_shift_rel, 3)],
        ['untangle_path', s.untangle_path], ['certificate_passes', s.certificate_passes],
        ['local_certificate_passes', s.local_certificate_passes],
        // The GPC job's retried constructions (only those that ran): what was tried and kept.
        ...Object.entries(s.domain_retries ?? {}),
        ['cut_min_scaled_jacobian', fmt(this.result.cut.min_scaled_jacobian, 3)],
        ['time_s', fmt(s.times_s.total, 3)], ['worker_ms', fmt(this.result.ms_worker, 4)],
      ]);
      return;
    }
    fillStats($('mesh-stats'), [
      ['file', i.file], ['vertices', i.vertices], ['faces', i.faces], ['genus', i.genus === null ? 'undefined' : i.genus],
      ['fit', s.fit], ['rms_rel', fmt(s.rms_rel, 3)], ['max_rel', fmt(s.max_rel, 3)],
      ['hausdorff_rel', fmt(s.hausdorff_rel, 3)], ['rms_geo_rel', fmt(s.rms_geo_rel, 3)],
      ['control_points', s.control_points], ['levels', s.levels], ['cuboids', s.cuboids],
      ...certificateRows(s),
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
      markUncertified(r, this.result.stats);
      this.result.cut = r;
      this.view?.setCut(r);
      const td = document.querySelector('#mesh-stats td[data-key="cut_min_scaled_jacobian"]');
      if (td) td.textContent = fmt(r.min_scaled_jacobian, 3);
      this.showVerdict();
    } finally {
      this.cutRunning = false;
      if (this.cutPending) this.updateCut();
    }
  },

  /// Adds a job that runs on the open mesh: `button` (an element) starts it with `options()`,
  /// `render(result)` shows its result, `reset()` (optional) clears it when another mesh or result
  /// replaces it. The job gets {bytes, name, options} like mesh2spline; its result's `stats` are
  /// the stats download.
  /// Returns the start function (what a click does): resolves when the job has finished.
  addRun({ button, job, options, render, reset = null }) {
    const start = async () => {
      if (!this.bytes || jobs.busy) return;
      clearError();
      button.disabled = true;
      const opts = options();
      const r = await runJob(job, { bytes: this.bytes.slice(), name: this.name, options: opts });
      button.disabled = false;
      if (!r.ok) {
        if (r.message !== 'cancelled') showError(r.message);
        this.markStale(job, opts, r.message === 'cancelled' ? 'was cancelled' : 'failed');
        return;
      }
      this.clearResults();
      this.lastRun = { job, options: opts, result: r };
      // The input mesh would hide the result: shown again by its checkbox.
      $('mesh-show-input').checked = false;
      if (this.view) this.view.visible.input = false;
      render(r);
    };
    this.runs.push({ button, job, reset, start });
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
for (const layer of ['input', 'wireframe', 'boundary', 'lines', 'control', 'lattice', 'cut', 'folds', 'cuboids', 'poly_edges']) {
  $('mesh-show-' + layer).addEventListener('change', (e) => {
    if (!meshTab.view) return;
    meshTab.view.visible[layer] = e.target.checked;
    meshTab.view.requestDraw();
  });
}
$('mesh-run').addEventListener('click', () => meshTab.run());
$('mesh-show-distance').addEventListener('change', () => meshTab.applyQuality());
// Values under the cursor, once per animation frame while the pointer moves without a button.
{
  let pending = 0, last = null;
  $('mesh-canvas').addEventListener('pointermove', (e) => {
    if (e.buttons) return;
    last = e;
    if (!pending) pending = requestAnimationFrame(() => { pending = 0; meshTab.probe(last.clientX, last.clientY); });
  });
  $('mesh-canvas').addEventListener('pointerleave', () => { $('mesh-probe').textContent = ''; });
}
$('mesh-fit-view').addEventListener('click', () => meshTab.view?.fitView());
$('mesh-view-axis').addEventListener('change', (e) => {
  if (e.target.value) meshTab.view?.viewFrom(e.target.value);
  e.target.value = '';
});
$('mesh-screenshot').addEventListener('click', async () => {
  if (!meshTab.view) return;
  try {
    download(await meshTab.view.screenshot(), (meshTab.name ? baseName(meshTab.name) : 'volspline') + '.view.png', 'image/png');
  } catch (e) {
    showError(e.message);
  }
});
$('mesh-cut-axis').addEventListener('change', () => meshTab.updateCut());
$('mesh-cut-position').addEventListener('input', () => { $('mesh-cut-value').textContent = $('mesh-cut-position').value; meshTab.updateCut(); });
$('mesh-download-json').addEventListener('click', () => download(meshTab.result.spline_json, baseName(meshTab.name) + '.spline.json', 'application/json'));
$('mesh-download-glb').addEventListener('click', () => download(meshTab.result.glb, baseName(meshTab.name) + '.spline.glb', 'model/gltf-binary'));
$('mesh-download-vtu').addEventListener('click', () => download(meshTab.result.vtu, baseName(meshTab.name) + '.spline.vtu', 'application/xml'));
$('mesh-download-stats').addEventListener('click', () => {
  const suffix = meshTab.lastRun ? `.${meshTab.lastRun.job}.stats.json` : meshTab.result ? '.stats.json' : '.info.json';
  download(JSON.stringify(meshTab.statsJson(), null, 2) + '\n', baseName(meshTab.name) + suffix, 'application/json');
});

