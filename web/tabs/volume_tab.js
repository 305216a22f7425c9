// SPDX-License-Identifier: MIT
// The Volume tab: open a volume, slices along x, y or z coloured by density within a window
// (window/level as fractions of the volume's range), vol2spline's density or its difference
// |input − spline| on the same slice beside it, the stats and the spline download.
import { MeshView } from '../mesh_view.js';
import { isoSurface } from '../iso_surface.js';
import { $, jobs, runJob, showError, clearError, download, acceptFiles, fillStats, fmt, baseName, markStale } from '../ui.js';

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

export const volumeTab = {
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
    markStale([$('volume-fit-figure'), $('volume-stats')], $('volume-stale'), '');
    $('volume-hint').hidden = true;
    $('volume-fit-figure').hidden = true;
    $('volume-run').disabled = !jobs.available?.includes('vol2spline');
    $('volume-download-json').disabled = true;
    this.setAxis();
    this.showStats();
    this.isoKey = null;
    this.drawIso();
  },

  /// Runs vol2spline on the loaded volume and shows the spline's density beside the input.
  async run() {
    const v = this.volume;
    if (!v || jobs.busy) return;
    clearError();
    $('volume-run').disabled = true;
    const options = { max_levels: Number($('volume-levels').value), max_rms_rel: Number($('volume-max-rms').value) };
    const volume = { nx: v.nx, ny: v.ny, nz: v.nz, spacing: v.spacing, origin: v.origin, direction: v.direction, samples: v.samples.slice() };
    const r = await runJob('vol2spline', { volume, name: v.name, options }, { transfer: [volume.samples.buffer] });
    $('volume-run').disabled = false;
    const staleParts = [$('volume-fit-figure'), $('volume-stats')];
    if (!r.ok) {
      if (r.message !== 'cancelled') showError(r.message);
      if (this.fit && this.volume === v)
        markStale(staleParts, $('volume-stale'), `vol2spline (levels ${options.max_levels}, rms ${options.max_rms_rel}) ${r.message === 'cancelled' ? 'was cancelled' : 'failed'}: ` +
                  `the spline shown is the previous run's (levels ${this.fit.options.max_levels}, rms ${this.fit.options.max_rms_rel})`);
      return;
    }
    if (this.volume !== v) return;  // another volume was opened meanwhile
    markStale(staleParts, $('volume-stale'), '');
    this.fit = { density: r.reconstruction, stats: r.stats, spline_json: r.spline_json, options };
    $('volume-fit-figure').hidden = false;
    $('volume-download-json').disabled = false;
    this.draw();
    this.showStats();
    if ($('volume-iso-source').value === 'spline') this.drawIso();
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

  /// The density window [lo, hi] of the sliders (fractions of min … max, kept in order).
  window() {
    const v = this.volume;
    let a = Number($('volume-window-lo').value), b = Number($('volume-window-hi').value);
    if (a > b) [a, b] = [b, a];
    if (b - a < 0.01) b = Math.min(1, a + 0.01), a = b - 0.01;
    return [v.min + a * (v.max - v.min), v.min + b * (v.max - v.min)];
  },

  draw() {
    const v = this.volume;
    if (!v) return;
    const axis = Number($('volume-axis').value), index = Number($('volume-slice').value);
    $('volume-slice-value').textContent = `${'xyz'[axis]} = ${index}`;
    const [lo, hi] = this.window();
    const full = lo === v.min && hi === v.max;
    $('volume-window-value').textContent = full ? 'full range' : `${fmt(lo, 3)} … ${fmt(hi, 3)}`;
    $('volume-legend-min').textContent = fmt(lo, 3);
    $('volume-legend-max').textContent = fmt(hi, 3);
    this.paint($('volume-canvas'), v.samples, axis, index, lo, hi);
    if (!this.fit) return;
    if ($('volume-fit-mode').value === 'difference') {
      // |input − spline| over the whole volume, coloured from 0 to its largest value.
      const f = this.fit;
      if (!f.difference) {
        f.difference = new Float32Array(v.samples.length);
        let max = 0;
        for (let i = 0; i < v.samples.length; i++) max = Math.max(max, (f.difference[i] = Math.abs(v.samples[i] - f.density[i])));
        f.differenceMax = max;
      }
      this.paint($('volume-fit-canvas'), f.difference, axis, index, 0, f.differenceMax || 1);
      $('volume-fit-caption').textContent = `0 … ${fmt(f.differenceMax, 3)} (${fmt(100 * f.differenceMax / (v.max - v.min || 1), 3)} % of the range)`;
    } else {
      this.paint($('volume-fit-canvas'), this.fit.density, axis, index, lo, hi);
      $('volume-fit-caption').textContent = '';
    }
  },

  /// The iso-surface view: the surface at the slider's level of the input or the spline density,
  /// in voxel units times spacing, sampled every `step` voxels so that at most ~96 cells lie along
  /// an axis (the view stays interactive on big volumes).
  drawIso() {
    const v = this.volume;
    const show = !!v && $('volume-show-iso').checked;
    $('volume-iso-figure').hidden = !show;
    if (!show) return;
    if (!this.isoView) {
      try {
        this.isoView = new MeshView($('volume-iso-canvas'));
        this.isoView.visible.wireframe = false;
      } catch (e) { showError(e.message); return; }
    }
    const fraction = Number($('volume-iso-level').value);
    const fromSpline = $('volume-iso-source').value === 'spline' && this.fit;
    const level = v.min + fraction * (v.max - v.min);
    const step = Math.max(1, Math.ceil(Math.max(v.nx, v.ny, v.nz) / 96));
    const spacing = v.spacing ?? [1, 1, 1];
    const t0 = performance.now();
    const { positions, triangles } = isoSurface(fromSpline ? this.fit.density : v.samples, v.nx, v.ny, v.nz, level, { spacing, step });
    const ms = performance.now() - t0;
    const lo = [0, 0, 0], hi = [0, 1, 2].map((k) => spacing[k] * ([v.nx, v.ny, v.nz][k] - 1));
    const key = `${v.name}|${v.nx}|${v.ny}|${v.nz}`;
    if (this.isoKey !== key) { this.isoView.setMesh(positions, triangles, lo, hi); this.isoView.fitView(); this.isoKey = key; }
    else this.isoView.setLayer('input', { positions, indices: triangles });
    $('volume-iso-value').textContent = fmt(level, 3);
    $('volume-iso-caption').textContent = `${fromSpline ? 'spline' : 'input'} density = ${fmt(level, 3)}: ${triangles.length / 3} triangles` +
      `${step > 1 ? `, every ${step} voxels` : ''} (${ms.toFixed(0)} ms)`;
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
  },
};
$('volume-legend-bar').style.background = `linear-gradient(to right, ${DENSITY_STOPS.map(([t, c]) => `rgb(${c.join(',')}) ${100 * t}%`).join(', ')})`;
acceptFiles($('panel-volume'), $('volume-file'), (b, n) => volumeTab.open(b, n));
$('volume-axis').addEventListener('change', () => volumeTab.setAxis());
$('volume-slice').addEventListener('input', () => volumeTab.draw());
for (const id of ['volume-window-lo', 'volume-window-hi']) $(id).addEventListener('input', () => volumeTab.draw());
$('volume-fit-mode').addEventListener('change', () => volumeTab.draw());
for (const id of ['volume-show-iso', 'volume-iso-source']) $(id).addEventListener('change', () => volumeTab.drawIso());
$('volume-iso-level').addEventListener('change', () => volumeTab.drawIso());
$('volume-iso-level').addEventListener('input', () => {
  const v = volumeTab.volume;
  if (v) $('volume-iso-value').textContent = fmt(v.min + Number($('volume-iso-level').value) * (v.max - v.min), 3);
});
$('volume-run').addEventListener('click', () => volumeTab.run());
$('volume-download-json').addEventListener('click', () => {
  const f = volumeTab.fit;
  if (f) download(f.spline_json, baseName(volumeTab.volume.name) + '.spline.json', 'application/json');
});

