// SPDX-License-Identifier: Apache-2.0
// Fuzz target: motions (.mot/.sto storage files) mapped onto the hip skeleton of models/hip, and
// the first frames of an accepted motion posed: every body must stay finite.
#include <algorithm>
#include <memory>

#include "fuzz_support.h"
#include "model/model_error.h"
#include "model/motion.h"
#include "model/skeleton.h"
#include "model/storage_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rbfmuscle;
  static Skeleton* skeleton = new Skeleton(Skeleton::fromUrdf(RBFMUSCLE_SOURCE_DIR "/models/hip/hip_r.urdf"));
  try {
    const StorageTable table = parseStorageText(fuzz::asText(data, size), "fuzz.mot");
    const Motion motion = Motion::fromTable(table, "fuzz.mot", *skeleton);
    for (int frame = 0; frame < std::min(motion.getNumFrames(), 4); ++frame) {
      skeleton->setCoordinateValues(motion.getCoordinates(frame));
      for (int b = 0; b < static_cast<int>(skeleton->getBodyNames().size()); ++b)
        fuzz::requireThat(skeleton->getBodyTransform(b).matrix().allFinite(), "bodies follow a motion finitely");
    }
  } catch (const ModelError&) {
  }
  return 0;
}
