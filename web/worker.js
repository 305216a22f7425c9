// SPDX-License-Identifier: MIT
// @ts-check
// The Web Worker that owns the WebAssembly core. Only this file loads volspline.mjs.
// Messages in:  {type:'init', cancel: SharedArrayBuffer|null}
//               {type:'run', id, job, args}
// Messages out: {type:'ready', version, jobs} | {type:'fatal', message}
//               {type:'progress', id, stage, fraction} | {type:'result', id, result, ms}
// Every job result is the core's {ok, ...} object; typed arrays in it are transferred, not copied.
// The message types are in messages.js.
import createVolspline from './volspline.mjs';

let core = null;
let cancelFlag = null;  // Int32Array over a SharedArrayBuffer: 1 asks the running job to stop
const images = new Map();  // decoded images by key, so live lens runs do not resend pixels
// One core LensSession per image key: it keeps the lens mesh, texture, factorization and calibrated
// h0 between runs, so an α change at a known height only re-runs the flattening iterations.
const sessions = new Map();
const sessionFor = (key) => {
  if (!sessions.has(key)) sessions.set(key, new core.LensSession());
  return sessions.get(key);
};

const transferables = (value, out = []) => {
  if (ArrayBuffer.isView(value)) out.push(value.buffer);
  else if (value && typeof value === 'object') for (const v of Object.values(value)) transferables(v, out);
  return out;
};

const jobs = {
  meshInfo: ({ bytes, name }) => core.meshInfo(bytes, name),
  mesh2spline: ({ bytes, name, options }, progress) => core.mesh2spline(bytes, name, options, progress),
  gpc: ({ bytes, name, options }, progress) => core.gpc(bytes, name, options, progress),
  splineCut: ({ json, axis, position, samples }) => core.splineCut(json, axis, position, samples),
  splineQuality: ({ json, bytes, name, options }) => core.splineQuality(json, bytes ?? null, name ?? '', options),
  loadVolume: ({ bytes, name, layout }) => core.loadVolume(bytes, name, layout ?? null),
  vol2spline: ({ volume, name, options }, progress) => core.vol2spline(volume, name, options, progress),
  // Decodes once and keeps the image under `key`; returns it for the page's texture.
  setImage: ({ key, bytes, name }) => {
    const r = core.decodeImage(bytes, name);
    if (!r.ok) return r;
    r.image.name = name;
    for (const session of sessions.values()) session.delete();  // Embind objects are freed by hand
    sessions.clear();
    images.clear();  // the page shows one image at a time
    images.set(key, r.image);
    const copy = { ...r.image, pixels: r.image.pixels.slice() };
    return { ok: true, image: copy };
  },
  lens: ({ key, rois, options }, progress) => {
    const image = images.get(key);
    if (!image) return { ok: false, message: 'no image loaded' };
    return sessionFor(key).run(image, rois, options, progress);
  },
  // Runs the lens with the core rasterizer and returns the PNG bytes.
  lensPng: ({ key, rois, options }, progress) => {
    const image = images.get(key);
    if (!image) return { ok: false, message: 'no image loaded' };
    const r = sessionFor(key).run(image, rois, { ...options, render: true }, progress);
    if (!r.ok) return r;
    const png = core.encodePng(r.image);
    return png.ok ? { ok: true, bytes: png.bytes, stats: r.stats } : png;
  },
};

// Jobs that need a binding which older builds of the core may lack.
const bindingOf = { mesh2spline: 'mesh2spline', gpc: 'gpc', splineCut: 'splineCut', splineQuality: 'splineQuality', loadVolume: 'loadVolume', vol2spline: 'vol2spline' };

/** @param {import('./messages.js').RunMessage} message @returns {import('./messages.js').JobResult} */
function run({ id, job, args }) {
  if (!jobs[job]) return { ok: false, message: `unknown job '${job}'` };
  let last = 0;
  const progress = (stage, fraction) => {
    const now = performance.now();
    if (now - last > 50 || fraction >= 1) {  // throttle: the page repaints at most ~20 times a second
      last = now;
      postMessage({ type: 'progress', id, stage, fraction });
    }
    return !(cancelFlag && Atomics.load(cancelFlag, 0) === 1);
  };
  try {
    return jobs[job](args, progress);
  } catch (e) {
    // The bindings never throw for bad data; this is a JS-side bug or a wasm trap.
    return { ok: false, message: 'internal error: ' + (e && e.message ? e.message : String(e)) };
  }
}

onmessage = async (/** @type {MessageEvent<import('./messages.js').ToWorker>} */ event) => {
  const msg = event.data;
  if (msg.type === 'init') {
    cancelFlag = msg.cancel ? new Int32Array(msg.cancel) : null;
    try {
      core = await createVolspline();
      // A job is offered only if this build of the core has its binding.
      const available = Object.keys(jobs).filter((j) => !(j in bindingOf) || typeof core[bindingOf[j]] === 'function');
      postMessage({ type: 'ready', version: core.version(), jobs: available });
    } catch (e) {
      postMessage({ type: 'fatal', message: 'the WebAssembly core did not load: ' + e });
    }
  } else if (msg.type === 'run') {
    const t0 = performance.now();
    const result = run(msg);
    postMessage({ type: 'result', id: msg.id, result, ms: performance.now() - t0 }, transferables(result));
  }
};
