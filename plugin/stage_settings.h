// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// The settings of a muscle's frame stages a user may change, each a subcomponent of the
/// RBFMuscle (subcomponent.h): `<fibres>`, `<volume>` and `<descent>` elements inside the
/// muscle's element. Their defaults are the recommended settings for any muscle.
#include "framework/subcomponent.h"

namespace rbfmuscle {

/// `<fibres>`: the fibres whose lengths the muscle reports.
class FibreSubcomponent final : public Subcomponent {
 public:
  explicit FibreSubcomponent(Component* owner)
      : Subcomponent(owner, "fibres", "fibres from the origin area to the insertion area, through the muscle") {}
  Property<int> count{this, "count", 100, "fibres (0 = none)", PropertyRange{0, 10000}};
  Property<int> segments{this, "segments", 15, "segments per fibre (its shape is made at 15 and sampled at this count)", PropertyRange{1, 1000}};
};

/// `<volume>`: the volume measure and its correction.
class VolumeSubcomponent final : public Subcomponent {
 public:
  explicit VolumeSubcomponent(Component* owner)
      : Subcomponent(owner, "volume", "the volume measure, kept at its rest value each frame") {}
  Property<int> quadrature_points{this, "quadrature_points", 2000,
                                  "points of the volume measure over the muscle and a shell around it",
                                  PropertyRange{64, 200000}};
  Property<double> max_correction{this, "max_correction", 0.5,
                                  "largest |δ| of the volume correction: the free kernels' weights change by at "
                                  "most this fraction of themselves each frame",
                                  PropertyRange{1e-6, 10.0}};
};

/// `<descent>`: the curvature descent after the tissue map.
class DescentSubcomponent final : public Subcomponent {
 public:
  explicit DescentSubcomponent(Component* owner)
      : Subcomponent(owner, "descent", "curvature-preserving descent of the free kernels after the tissue map") {}
  Property<int> iterations{this, "iterations", 1, "L-BFGS steps per frame (0 = the tissue map alone)",
                           PropertyRange{0, 1000}};
};

}  // namespace rbfmuscle
