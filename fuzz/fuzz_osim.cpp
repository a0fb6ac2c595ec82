// SPDX-License-Identifier: Apache-2.0
// Fuzz target: OpenSim models (.osim, 3.x and 4.x layouts), read (osim_description.cpp and its
// joints in osim_joints.cpp) and built into a Simbody system; an accepted skeleton must pose its
// bodies finitely at rest. The text stands for a file in models/hip/osim, so the geometry it
// names may exist there.
#include "fuzz_support.h"
#include "model/model_error.h"
#include "model/skeleton.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rbfmuscle;
  try {
    Skeleton skeleton =
        Skeleton::fromOsimText(fuzz::asText(data, size), RBFMUSCLE_SOURCE_DIR "/models/hip/osim/fuzz.osim");
    skeleton.setCoordinateValues(skeleton.getRestCoordinateValues());
    for (int b = 0; b < static_cast<int>(skeleton.getBodyNames().size()); ++b)
      fuzz::requireThat(skeleton.getBodyTransform(b).matrix().allFinite(), "bodies of a skeleton pose finitely");
  } catch (const ModelError&) {
  }
  return 0;
}
