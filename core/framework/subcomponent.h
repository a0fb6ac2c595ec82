// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// A component nested in another, as OpenSim nests components: a member of its owner that
/// groups the settings of one part (a muscle's fibres, its volume step), with properties of its
/// own. In the model file it is a child element of the owner's element, named after it and
/// holding its properties; on the command line its path is OWNER/NAME:
///
///     <RBFMuscle name="iliacus_r"> … <fibres><count>50</count></fibres> </RBFMuscle>
///     rbfmuscle run MODEL.xml -o OUT --set iliacus_r/fibres.count=50
///
/// It does no work per frame: its owner reads its properties when it initializes.
#include "framework/component.h"

#include <string>

namespace rbfmuscle {

class Subcomponent : public Component {
 public:
  /// Registers with `owner` under `name` (also its class name in messages).
  Subcomponent(Component* owner, std::string name, std::string description)
      : description_(std::move(description)) {
    setName(name);
    setClassName(std::move(name));
    owner->subcomponents_.push_back(this);
  }
  const std::string& getDescription() const { return description_; }
  void update(const FrameState& state) override { (void)state; }

 private:
  std::string description_;
};

}  // namespace rbfmuscle
