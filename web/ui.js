// SPDX-License-Identifier: MIT
// @ts-check
// Shared UI of the page: the job client and its bar (progress, cancel), error display, file
// picking and drag-and-drop, the samples menus, downloads and the stats tables.
import { JobClient } from './job_client.js';

/** @param {string} id @returns {any} the element with that id (the page's ids are fixed) */
export const $ = (id) => document.getElementById(id);
export const jobs = new JobClient();

// The core names option fields in backticks (`max_rms_rel`); the page shows its own labels.
const FIELD_LABELS = {
  max_rms_rel: 'the max rms setting', max_levels: 'the levels setting', rois: 'a lens on the image',
  raw_layout: 'the raw dims and type fields', corners: 'other corners', magnification: 'the magnification',
  alpha: 'α', grid: 'the grid setting', max_pixels: 'the image size limit', max_voxels: 'the volume size limit',
};
function withLabels(message) {
  return String(message).replace(/`([a-z][a-z0-9_]*)`/g, (all, field) => FIELD_LABELS[field] || field.replace(/_/g, ' '));
}
export function showError(message) {
  $('error-text').textContent = withLabels(message);
  $('error').hidden = false;
}
export function clearError() { $('error').hidden = true; $('error-text').textContent = ''; }
$('error-close').addEventListener('click', clearError);
window.addEventListener('unhandledrejection', (e) => showError('unexpected error: ' + (e.reason?.message || e.reason)));

export function setProgress(stage, fraction) {
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

// The core's stage names in plain words (a name not listed is shown as it is).
const STAGE_WORDS = {
  validate: 'checking the input', 'cuboid layout': 'placing the cuboid corners', 'surface map': 'mapping the surface onto the cuboid',
  'volumetric map': 'mapping the volume', fit: 'fitting the spline', untangle: 'unfolding the spline',
  'untangle pass': 'unfolding the spline', 'untangle polish': 'polishing the unfolded spline', 'untangle certificate': 'unfolding the uncertified cells',
  'untangle: cuboids': 'unfolding the spline cuboid by cuboid', 'untangle: certificate round': 'unfolding the uncertified cells',
  'Jacobian repair': 'repairing the Jacobian', measures: 'measuring the fit', measure: 'measuring the fit', certificate: 'certifying det J > 0 cell by cell',
  'uniform comparison': 'fitting a uniform spline to compare', 'local cubic fit': 'fitting local cubics to the voxels',
  'hessian frames': 'frames from the Hessians', classification: 'classifying the materials', parameterization: 'aligning the parameters with the frames',
  'smooth frames': 'smoothing the frames', decompose: 'cutting the solid into pieces', 'T-to-cube': 'laying the pieces out as cuboids',
  'grid untangling': 'unfolding the volume grid', padding: 'padding the grid under the surface',
  read: 'reading the file', flatten: 'flattening the lens', done: 'done',
};
const JOB_WORDS = { meshInfo: 'reading the mesh', mesh2spline: 'mesh2spline', gpc: 'GPC domain', loadVolume: 'reading the volume',
  vol2spline: 'vol2spline', splineQuality: 'quality views', splineCut: 'cut', setImage: 'reading the image', lens: 'lens', lensPng: 'lens PNG' };
/** @param {string} stage @returns {string} the core's stage name in plain words */
export const stageWords = (stage) => {
  const trimmed = String(stage).trim();
  const level = /^fit level (\d+)$/.exec(trimmed);
  if (level) return `fitting the spline, level ${level[1]}`;
  const words = STAGE_WORDS[trimmed] ?? STAGE_WORDS[trimmed.replace(/ \d.*$/, '')];
  if (words) return words;
  // A retried or repeated stage ("refit: untangle: cuboids", "caps at the poles: T-to-cube"): its
  // prefix as it is, the stage after it in words.
  const colon = trimmed.indexOf(': ');
  return colon > 0 ? `${trimmed.slice(0, colon)}: ${stageWords(trimmed.slice(colon + 2))}` : trimmed;
};

/// Runs a job with the job bar; long-running or not, the UI stays responsive (the worker computes).
/// The bar names the stage in plain words with its share of the job and the seconds spent in it,
/// updated twice a second also while the core reports nothing.
/**
 * @param {import('./messages.js').JobName} job
 * @param {object} args
 * @param {{quiet?: boolean, transfer?: Transferable[]}} [options]
 * @returns {Promise<import('./messages.js').JobResult>}
 */
export async function runJob(job, args, { quiet = false, transfer = [] } = {}) {
  const name = JOB_WORDS[job] ?? job;
  let stage = '', fraction = 0, since = performance.now();
  const show = () => {
    const seconds = (performance.now() - since) / 1000;
    setProgress(stage ? `${name}: ${stageWords(stage)} · ${Math.round(100 * fraction)} %${seconds >= 1 ? ` (${seconds.toFixed(0)} s)` : ''}` : name + '…', fraction);
  };
  if (!quiet) show();
  const ticker = quiet ? 0 : setInterval(show, 500);
  // Quiet jobs (the lens's live runs) leave the bar alone: its text would re-lay out the page every frame.
  const onProgress = quiet ? null : (s, f) => {
    if (s !== stage) { stage = s; since = performance.now(); }
    fraction = f;
    show();
  };
  const result = await jobs.run(job, args, { transfer, onProgress });
  clearInterval(ticker);
  if (!quiet || !result.ok) setProgress(result.ok ? `${name}: done (${result.ms_worker.toFixed(0)} ms)` : `${name}: ${result.message === 'cancelled' ? 'cancelled' : 'failed'}`, result.ok ? 1 : 0);
  return result;
}

/// Marks what a tab shows as stale (a run was cancelled or failed; the view and stats are the
/// previous run's): dims `elements` and shows `text` in `notice`; an empty text clears it.
export function markStale(elements, notice, text) {
  for (const e of elements) e.classList.toggle('stale', !!text);
  notice.textContent = text;
  notice.hidden = !text;
}

export function download(bytes, name, type) {
  const url = URL.createObjectURL(new Blob([bytes], { type }));
  const a = document.createElement('a');
  a.href = url; a.download = name;
  document.body.append(a); a.click(); a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 10000);
}
export const readFile = async (file) => new Uint8Array(await file.arrayBuffer());

/// Wires a panel's file input and drag-and-drop to `open(bytes, name)`.
export function acceptFiles(panel, input, open) {
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
export function samplesMenu(select, kind, list, open) {
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

// Readable labels, with units and what a relative measure is relative to, for the stats keys
// (the key stays the cell's data-key, as in the downloaded JSON).
const LABELS = {
  rms_rel: 'RMS distance to the mesh (÷ bbox diagonal)', max_rel: 'max distance to the mesh (÷ bbox diagonal)',
  hausdorff_rel: 'Hausdorff distance (÷ bbox diagonal)', rms_geo_rel: 'RMS geometric distance (÷ bbox diagonal)',
  min_corner_distance_rel: 'min corner distance (÷ bbox diagonal)', semi_standard_max_error: 'semi-standard error (max |Σ w B − 1|)',
  control_points: 'control points', min_scaled_jacobian: 'min scaled Jacobian (Gauss points)',
  jacobian_certified_fraction: 'certified fold-free cells (det J ≥ 0 proven)', det_j_lower_bound_rel: 'certified lower bound of the scaled Jacobian',
  certificate_cells: 'cells certified or not', uncertified_cells: 'cells not certified', negative_jacobian_fraction: 'folded fraction (det J ≤ 0)',
  grid_inverted_hexes: 'inverted grid hexes', grid_min_scaled_jacobian: 'grid min scaled Jacobian',
  cut_min_scaled_jacobian: 'cut min scaled Jacobian', time_s: 'core time (s)', worker_ms: 'worker time (ms)',
  magnification_center: 'magnification at the centre', magnification_per_roi: 'magnification per lens', height_scale_per_roi: 'height per lens (÷ h0)', magnification_requested: 'magnification asked',
  magnification_limited: 'limited by the fold-free guard', distortion_sum: 'distortion Σ (Eq. 6.9)',
  distortion_max: 'distortion max (0..1)', distortion_max_focus: 'distortion max in the focus (0..1)',
  flipped_triangles: 'flipped triangles', ms_per_iteration: 'per iteration (ms)', ms_total: 'total (ms)',
  ms_calibration: 'calibration (ms)', ms_factorize: 'factorization (ms)', height: 'lens height h0 (ROI radii)',
  baseline_parameter: 'baseline parameter', live_frame_ms: 'live frame (ms)', live_fps: 'live frames per second',
  density_rms_rel: 'density RMS error (÷ density range)', density_max_rel: 'density max error (÷ density range)',
  bbox_min: 'bbox min', bbox_max: 'bbox max', boundary_loops: 'boundary loops', euler_characteristic: 'Euler characteristic',
  consistently_oriented: 'consistently oriented', degenerate_faces: 'degenerate faces', signed_volume: 'signed volume',
  frame_smoothness_initial: 'frame smoothness before (Eq. 5.6)', frame_smoothness_final: 'frame smoothness after (Eq. 5.6)',
  t_shapes: 'T-shapes', ill_points: 'ill-points (Type 1)', interface_gap_rel: 'glued-face gap (÷ bbox diagonal)',
  grid_nodes: 'grid nodes', surface_vertices: 'surface vertices (refined along the cuts)',
  cut_disc_intersections: 'cut-disc crossings (meridian check, 0)', tightened_cuts: 'cuts moved to the shortest loop', limb_caps: 'limb caps',
  limb_fallback: 'limb construction dropped because', finer_limbs: 'retry with shorter limbs as caps',
  pole_caps: 'retry with caps at the poles', taller_centres: 'retry with taller T-shape centres',
  off_axis_poles: 'poles moved off the diameter', time_validate_s: 'validate (s)',
  time_decompose_s: 'decompose (s)', time_t_to_cube_s: 'T-to-cube (s)', time_volumetric_map_s: 'volumetric map (s)',
};
/** @param {string} key @returns {string} the label shown for a stats key */
export const statLabel = (key) => LABELS[key] ?? key.replace(/_/g, ' ');

export function fillStats(table, rows) {
  table.replaceChildren(...rows.map(([k, v]) => {
    const tr = document.createElement('tr');
    const th = document.createElement('th'); th.textContent = statLabel(k); th.scope = 'row';
    const td = document.createElement('td'); td.textContent = v; td.dataset.key = k;
    tr.append(th, td);
    return tr;
  }));
}
/** Numbers with `digits` significant digits, in plain notation from 1e-4 to 1e9 (never "1.2e+3"). */
export const fmt = (x, digits = 4) => {
  if (typeof x !== 'number') return String(x);
  if (Number.isInteger(x)) return String(x);
  const a = Math.abs(x);
  return a >= 1e-4 && a < 1e9 ? String(Number(x.toPrecision(digits))) : x.toPrecision(digits);
};
export const baseName = (name) => name.replace(/\.[^.]*$/, '');
