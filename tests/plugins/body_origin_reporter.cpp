// SPDX-License-Identifier: Apache-2.0
#include "body_origin_reporter.h"

#include "framework/registry.h"

namespace rbfmuscle::testplugin {

void BodyOriginReporter::initialize(const InitContext&) {
  declareInvariant({"x_mm", x_min_mm.get(), std::numeric_limits<double>::infinity(), "P stays at x >= x_min_mm"});
}

void BodyOriginReporter::update(const FrameState& state) {
  result_.p_GP_mm = state.getBodyTransform(body) * point_mm.get();
}

}  // namespace rbfmuscle::testplugin

/// The plugin's one exported symbol.
extern "C" __attribute__((visibility("default"))) void rbfmuscle_register_types(
    rbfmuscle::Registry& registry) {
  registry.addType<rbfmuscle::testplugin::BodyOriginReporter>(
      "BodyOriginReporter", "reports a point fixed in a body (default: its origin) in ground, mm");
}
