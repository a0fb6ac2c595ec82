// SPDX-License-Identifier: Apache-2.0
// Fuzz target: fitted surfaces (.rbf). An accepted surface must evaluate to finite values, the
// promise the magnitude bounds of rbf_file.h make.
#include <Eigen/Core>

#include <cmath>

#include "fit/rbf_file.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rbfmuscle;
  try {
    const RbfSurface surface = parseRbfText(fuzz::asText(data, size), "fuzz.rbf");
    const GaussianField& field = surface.field;
    const Eigen::Vector3d probes[] = {Eigen::Vector3d::Zero(), field.getCentres().col(0),
                                      field.getCentres().col(0) + Eigen::Vector3d(0.5, -0.25, 1.0)};
    for (const Eigen::Vector3d& p : probes) {
      const FieldEvaluation e = field.calcEvaluation(p);
      fuzz::requireThat(std::isfinite(e.value), "a read surface has finite values");
      fuzz::requireThat(e.gradient.allFinite(), "a read surface has finite gradients");
      fuzz::requireThat(std::isfinite(field.calcMeanCurvature(p)), "a read surface has finite curvature");
    }
  } catch (const RbfFileError&) {
  }
  return 0;
}
