// SPDX-License-Identifier: Apache-2.0
#include "framework/output.h"

#include "framework/component.h"

namespace rbfmuscle {

AbstractOutput::AbstractOutput(Component* owner, std::string name, std::string unit,
                               std::string description)
    : name_(std::move(name)), unit_(std::move(unit)), description_(std::move(description)) {
  owner->outputs_.push_back(this);
}

}  // namespace rbfmuscle
