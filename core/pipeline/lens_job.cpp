// SPDX-License-Identifier: MIT
#include "core/pipeline/lens_job.h"

#include "core/pipeline/lens_session.h"

namespace volspline::pipeline {

LensResult run_lens(const LensInput& input, const LensOptions& options, const Progress& progress) {
  // A one-shot session: the job itself (calibration, fold-free search, stats) lives in lens_session.cpp.
  LensSession session;
  return session.run(input, options, progress);
}

}  // namespace volspline::pipeline
