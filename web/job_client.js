// SPDX-License-Identifier: MIT
// @ts-check
// Runs core jobs in the Web Worker: one job at a time, progress callbacks, cancellation.
// Cancellation first asks the job to stop through a shared flag that the core's progress callback
// reads (needs a cross-origin isolated page); if the job does not stop within `graceMs`, or the
// page is not isolated, the worker is terminated and a fresh one started.

/** @typedef {import('./messages.js').JobName} JobName */
/** @typedef {import('./messages.js').JobResult} JobResult */
/** @typedef {import('./messages.js').FromWorker} FromWorker */
/** @typedef {import('./messages.js').ToWorker} ToWorker */

export class JobClient {
  constructor({ workerUrl = './worker.js', graceMs = 1500 } = {}) {
    this.workerUrl = workerUrl;
    this.graceMs = graceMs;
    this.generation = 0;  // increases whenever a new worker starts (its cached images are gone)
    this.nextId = 1;
    this.current = null;  // {id, resolve, onProgress}
    this.listeners = new Set();
    this.start();
  }

  /// Resolves with {version, jobs} once the core has loaded; rejects with an Error on failure.
  ready() { return this.readyPromise; }

  /// Listener called with (state) where state is 'busy' or 'idle'.
  onState(listener) { this.listeners.add(listener); }

  get busy() { return this.current !== null; }

  start() {
    this.generation++;
    this.shared = typeof SharedArrayBuffer !== 'undefined' && self.crossOriginIsolated ? new SharedArrayBuffer(4) : null;
    this.flag = this.shared ? new Int32Array(this.shared) : null;
    this.worker = new Worker(this.workerUrl, { type: 'module' });
    this.readyPromise = new Promise((resolve, reject) => {
      this.worker.onmessage = (event) => this.handle(event.data, resolve, reject);
      this.worker.onerror = (event) => {
        event.preventDefault();
        const message = 'worker error: ' + (event.message || 'the worker script failed to load');
        reject(new Error(message));
        this.finish({ ok: false, message });
      };
    });
    this.readyPromise.catch(() => {});
    this.worker.postMessage({ type: 'init', cancel: this.shared });
  }

  /** @param {FromWorker} msg @param {(v: {version: string, jobs: JobName[]}) => void} resolve @param {(e: Error) => void} reject */
  handle(msg, resolve, reject) {
    if (msg.type === 'ready') resolve({ version: msg.version, jobs: msg.jobs });
    else if (msg.type === 'fatal') { reject(new Error(msg.message)); this.finish({ ok: false, message: msg.message }); }
    else if (msg.type === 'progress' && this.current && msg.id === this.current.id) this.current.onProgress?.(msg.stage, msg.fraction);
    else if (msg.type === 'result' && this.current && msg.id === this.current.id) this.finish({ ...msg.result, ms_worker: msg.ms });
  }

  finish(result) {
    const job = this.current;
    if (!job) return;
    clearTimeout(job.timer);
    this.current = null;
    for (const l of this.listeners) l('idle');
    job.resolve(result);
  }

  /// Runs `job` with `args` (typed arrays in args are copied unless listed in `transfer`).
  /// Resolves with the core's result object ({ok:false, message} on failure or cancel); never rejects.
  /// Only one job runs at a time: a second call while busy resolves {ok:false, message:'busy'}.
  /**
   * @param {JobName} job
   * @param {Object<string, any>} args
   * @param {{onProgress?: ((stage: string, fraction: number) => void) | null, transfer?: Transferable[]}} [options]
   * @returns {Promise<JobResult>}
   */
  async run(job, args, { onProgress, transfer = [] } = {}) {
    if (this.current) return { ok: false, message: 'busy: another job is running' };
    try {
      await this.readyPromise;
    } catch (e) {
      return { ok: false, message: e.message };
    }
    return new Promise((resolve) => {
      const id = this.nextId++;
      this.current = { id, resolve, onProgress };
      if (this.flag) Atomics.store(this.flag, 0, 0);  // cleared here, not in the worker: a cancel may precede the start
      for (const l of this.listeners) l('busy');
      this.worker.postMessage({ type: 'run', id, job, args }, transfer);
    });
  }

  /// Asks the running job to stop; its promise resolves {ok:false, message:'cancelled'}.
  cancel() {
    const job = this.current;
    if (!job) return;
    if (this.flag) {
      Atomics.store(this.flag, 0, 1);
      job.timer = setTimeout(() => this.restart(), this.graceMs);
    } else {
      this.restart();
    }
  }

  restart() {
    this.worker.terminate();
    this.finish({ ok: false, message: 'cancelled' });
    this.start();
  }
}
