// SPDX-License-Identifier: Apache-2.0
/// @file
/// The plugin's one exported symbol: registers its component types.
#include "framework/registry.h"
#include "rbf_muscle.h"

extern "C" __attribute__((visibility("default"))) void rbfmuscle_register_types(
    rbfmuscle::Registry& registry) {
  registry.addType<rbfmuscle::RBFMuscle>(
      "RBFMuscle", "muscle as a Gaussian RBF surface following the bones (curvature-preserving, volume kept)");
}
