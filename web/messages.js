// SPDX-License-Identifier: MIT
// @ts-check
// Types of the messages between the page (job_client.js) and the worker (worker.js), for
// `// @ts-check` in both; the module has no run-time content.

/**
 * A job the worker runs on the core.
 * @typedef {'meshInfo'|'mesh2spline'|'gpc'|'splineCut'|'splineQuality'|'loadVolume'|'vol2spline'|'setImage'|'lens'|'lensPng'} JobName
 */

/**
 * Page → worker: start the core; `cancel` is a 4-byte SharedArrayBuffer whose Int32 set to 1
 * asks the running job to stop (null when the page is not cross-origin isolated).
 * @typedef {{type: 'init', cancel: SharedArrayBuffer|null}} InitMessage
 */

/**
 * Page → worker: run `job` with `args` (the binding's arguments, typed arrays transferable).
 * @typedef {{type: 'run', id: number, job: JobName, args: Object<string, any>}} RunMessage
 */

/** @typedef {InitMessage|RunMessage} ToWorker */

/**
 * Worker → page: the core loaded (`version`) and offers `jobs`.
 * @typedef {{type: 'ready', version: string, jobs: JobName[]}} ReadyMessage
 */

/**
 * Worker → page: the core did not load.
 * @typedef {{type: 'fatal', message: string}} FatalMessage
 */

/**
 * Worker → page: the running job `id` is at `fraction` (0..1) of its stage `stage`.
 * @typedef {{type: 'progress', id: number, stage: string, fraction: number}} ProgressMessage
 */

/**
 * Worker → page: job `id` finished after `ms` in the worker with the core's `result`.
 * @typedef {{type: 'result', id: number, result: JobResult, ms: number}} ResultMessage
 */

/** @typedef {ReadyMessage|FatalMessage|ProgressMessage|ResultMessage} FromWorker */

/**
 * The core's answer: {ok: true, ...the job's fields} or {ok: false, message}; the page adds
 * ms_worker, the worker's time for the job in milliseconds.
 * @typedef {{ok: boolean, message?: string, ms_worker?: number} & Object<string, any>} JobResult
 */

export {};
