// SPDX-License-Identifier: MIT
// The Lens tab: open an image, add circular and rectangular lenses, drag or resize each, α,
// magnification, grid and method controls re-run the job live, a before/after toggle, timing and
// stats readouts, PNG and JSON downloads.
import { $, jobs, runJob, showError, clearError, download, acceptFiles, fillStats, fmt } from '../ui.js';
import { LensView } from '../lens_view.js';

/// Why a metric lens stays below the magnification asked.
export const LensNotes = {
  /// '' when the lens reaches the request (within 3 %, the core's magnification_limited margin).
  shortfall(s, method, alpha) {
    if (method !== 'metric' || !(s.magnification_center < 0.97 * s.magnification_requested)) return '';
    const asked = `magnification ${fmt(s.magnification_requested, 3)} asked, ${fmt(s.magnification_center, 3)} here`;
    // Eq. 6.8 blends the rigid and the conformal metric's scale; the conformal one lets every
    // triangle of the lifted lens shrink freely, so its extra area is no longer spread out over
    // the image: with the border pinned the flattening stays close to the identity.
    if (alpha > 0) {
      return `${asked}: α = ${alpha} blends in the conformal metric, which keeps angles but not lengths, so the lens's ` +
        'raised surface is flattened back toward the image instead of being spread out; a lower α magnifies more (α = 0 fully)';
    }
    // A request above what the fold-free lens reaches here is answered with the largest clean lens.
    const perLens = s.magnification_per_roi.length > 1 ? ` (per lens ${s.magnification_per_roi.map((m) => fmt(m, 3)).join(', ')})` : '';
    if (s.magnification_limited) return `magnification ${fmt(s.magnification_requested, 3)} asked: at most ${fmt(s.magnification_center, 3)}${perLens} here without folding the image`;
    return '';
  },
};

export const lensTab = {
  view: null,
  key: null,          // worker-side image key
  generation: 0,      // worker generation the image was sent to (a restarted worker lost it)
  bytes: null, name: null,
  calibrated: null,   // {magnification, grid, height, scales, limited}: reuse h0 and each lens's height while only the lenses' places and sizes or α change
  pending: false, running: false,
  lastFrame: 0, frameMs: [],  // intervals between live results shown (the frame time while dragging)
  frameLog: [],               // per live result: {ms (interval or 0), ms_total, ms_worker}; read by the e2e test
  result: null,

  /// The lenses, input pixels ({shape: 'circle', cx, cy, r} or {shape: 'rect', cx, cy, w, h}), and
  /// the selected one; the view holds them, since pointer and keys edit them there.
  get rois() { return this.view.rois; },
  get roi() { return this.view.roi; },

  /// The lenses as the core takes them: circle cx, cy, r; rect x, y, w, h (top-left corner).
  coreRois() {
    return this.rois.map((r) => (r.shape === 'rect'
      ? { shape: 'rect', values: [r.cx - r.w / 2, r.cy - r.h / 2, r.w, r.h] }
      : { shape: 'circle', values: [r.cx, r.cy, r.r] }));
  },

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
    this.view.setImage(r.image);
    this.view.setRois([{ shape: 'circle', cx: width / 2, cy: height / 2, r: Math.max(4, Math.round(Math.min(width, height) / 6)) }]);
    this.showLensList();
    $('lens-hint').hidden = true;
    this.update(false);
  },

  /// Adds a lens of `shape` ('circle' or 'rect') where it is farthest from the others, selects it.
  addLens(shape) {
    if (!this.key) return;
    const { width, height } = this.view.image;
    const size = Math.max(4, Math.round(Math.min(width, height) / 8));
    const spots = [];
    for (const fy of [0.25, 0.5, 0.75]) for (const fx of [0.25, 0.5, 0.75]) spots.push([fx * width, fy * height]);
    const room = ([x, y]) => Math.min(...this.rois.map((r) => Math.hypot(x - r.cx, y - r.cy)));
    const [cx, cy] = spots.reduce((best, p) => (room(p) > room(best) ? p : best));
    const roi = shape === 'rect' ? { shape, cx, cy, w: 2 * size, h: Math.round(1.4 * size) } : { shape, cx, cy, r: size };
    this.view.setRois([...this.rois, roi], this.rois.length);
    this.lensesChanged();
  },

  removeLens() {
    if (this.rois.length < 2) return;
    const rois = this.rois.filter((_, i) => i !== this.view.active);
    this.view.setRois(rois, Math.min(this.view.active, rois.length - 1));
    this.lensesChanged();
  },

  /// After a lens was added or removed: the height h0 is calibrated again for the new set.
  lensesChanged() {
    this.calibrated = null;
    this.showLensList();
    this.update(false);
  },

  /// The lens menu (which lens the keys and Remove act on) and the Remove button's state.
  showLensList() {
    const select = $('lens-active');
    select.replaceChildren(...this.rois.map((r, i) => {
      const option = document.createElement('option');
      option.value = String(i);
      option.textContent = `lens ${i + 1} (${r.shape === 'rect' ? 'rectangle' : 'circle'})`;
      return option;
    }));
    select.value = String(this.view.active);
    $('lens-remove').disabled = this.rois.length < 2;
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
      if (o.method === 'metric' && c && c.magnification === o.magnification && c.grid === o.grid) Object.assign(options, { height: c.height, height_scale: c.scales });
      const rois = this.coreRois();
      // The same request as the one on screen (e.g. the release after a drag) is not re-run.
      const request = JSON.stringify([this.key, this.generation, rois, options]);
      if (request === this.lastRequest && this.lastRun) {
        if (!this.live) { this.showTiming(this.lastRun); this.showStats(this.lastRun.stats, o); }
        return;
      }
      const r = await runJob('lens', { key: this.key, rois, options }, { quiet: this.live });
      if (!r.ok) { this.lastRequest = null; if (r.message !== 'cancelled') showError(r.message); return; }
      this.lastRequest = request;
      this.lastRun = r;
      if (o.method === 'metric' && !options.height) {
        this.calibrated = { magnification: o.magnification, grid: o.grid, height: r.stats.height, scales: r.stats.height_scale_per_roi,
                            limited: r.stats.magnification_limited };
      } else if (options.height && c.limited) {
        // The core says "limited" only when it calibrated: a run at the calibrated height of a
        // limited request is limited alike.
        r.stats.magnification_limited = true;
      }
      // Drawn at the next animation frame (onFrame below), while the worker already computes the
      // next request: the frame time is max(core, drawing), not their sum.
      this.view.setMesh(r.positions, r.texture, r.triangles);
      this.shownLive = this.live ? r : null;
      this.result = { image: this.name, rois, options: { ...o, height: r.stats.height || undefined, height_scale: r.stats.height_scale_per_roi }, stats: r.stats };
      // While dragging, the text readouts are refreshed at most every 200 ms (layout is not free).
      const now = performance.now();
      if (!this.live || now - (this.lastText ?? 0) > 200) {
        this.lastText = now;
        this.showTiming(r);
        this.showStats(r.stats, o);
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

  /// The stats table and, when the lens stays below the request, the line saying why.
  showStats(s, { method, alpha }) {
    const limit = $('lens-limit');
    limit.textContent = LensNotes.shortfall(s, method, alpha);
    limit.hidden = !limit.textContent;
    const median = (a) => { const b = [...a].sort((x, y) => x - y); return b.length ? b[b.length >> 1] : 0; };
    const rows = [
      ['method', method], ['magnification_center', fmt(s.magnification_center)],
      ['magnification_requested', fmt(s.magnification_requested)], ['magnification_limited', s.magnification_limited ? 'yes' : 'no'],
      ...(s.magnification_per_roi.length > 1 ? [['magnification_per_roi', s.magnification_per_roi.map((m) => fmt(m, 3)).join(', ')]] : []),
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
  lensTab.view = new LensView({ canvas: $('lens-canvas'), ring: $('lens-ring'), overlay: $('lens-overlay') }, (live) => lensTab.update(live));
  lensTab.view.onFrame = () => lensTab.onFrame();
  lensTab.view.onSelect = () => lensTab.showLensList();
} catch (e) {
  showError(e.message);
}
acceptFiles($('panel-lens'), $('lens-file'), (b, n) => lensTab.open(b, n));
for (const id of ['lens-alpha', 'lens-magnification']) {
  $(id).addEventListener('input', () => { $(id + '-value').textContent = $(id).value; lensTab.update(true); });
  $(id).addEventListener('change', () => lensTab.update(false));
}
$('lens-grid').addEventListener('change', () => lensTab.update(false));
$('lens-add-circle').addEventListener('click', () => lensTab.addLens('circle'));
$('lens-add-rect').addEventListener('click', () => lensTab.addLens('rect'));
$('lens-remove').addEventListener('click', () => lensTab.removeLens());
$('lens-active').addEventListener('change', () => { lensTab.view.active = Number($('lens-active').value); lensTab.view.placeRing(); });
$('lens-before').addEventListener('click', () => {
  const on = $('lens-before').getAttribute('aria-pressed') !== 'true';
  $('lens-before').setAttribute('aria-pressed', String(on));
  lensTab.view.setOriginal(on);
});
for (const radio of document.querySelectorAll('input[name="lens-method"]')) radio.addEventListener('change', () => lensTab.update(false));
$('lens-download-json').addEventListener('click', () => {
  download(JSON.stringify(lensTab.result, null, 2) + '\n', lensTab.name.replace(/\.[^.]*$/, '') + '.lens.json', 'application/json');
});
$('lens-download-png').addEventListener('click', async () => {
  if (lensTab.running) return;
  const o = lensTab.options();
  const c = lensTab.calibrated;
  const options = { ...o };
  if (o.method === 'metric' && c && c.magnification === o.magnification && c.grid === o.grid) Object.assign(options, { height: c.height, height_scale: c.scales });
  const result = await runJob('lensPng', { key: lensTab.key, rois: lensTab.coreRois(), options });
  if (!result.ok) { if (result.message !== 'cancelled') showError(result.message); return; }
  download(result.bytes, lensTab.name.replace(/\.[^.]*$/, '') + `.${o.method}.png`, 'image/png');
});

