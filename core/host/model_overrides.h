// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Command-line changes to a parsed model document, for sweeps without editing
/// the model file: `--set COMPONENT.PROPERTY=VALUE`, `--motion FILE` and `--report PATTERN`.
/// They act on the document before any component is built, so a bad property
/// name or value is reported by Model::build like one written in the XML, with
/// the location "command line: --set ...".
#include "framework/model_document.h"

#include <string>
#include <vector>

namespace rbfmuscle {

/// Sets (or adds) property PROPERTY of component COMPONENT to the text VALUE.
/// `assignment` is "COMPONENT.PROPERTY=VALUE", or "COMPONENT/SUB.PROPERTY=VALUE" (also
/// written "COMPONENT.SUB/PROPERTY=VALUE", as `rbfmuscle info` lists it) for a property of
/// subcomponent SUB (subcomponent.h); names hold no '.' or '/', VALUE may be
/// empty and may contain '=', '.' and spaces. An unknown subcomponent is refused when the
/// model is built, listing the component's.
/// @throws UsageError when `assignment` is not of that form;
///   FrameworkError naming the assignment and listing the model's components
///   when no component is called COMPONENT.
void applyPropertyOverride(ModelDocument& document, const std::string& assignment);

/// Replaces the motion file by `path` (relative to the current directory).
/// Errors reading it later name "command line: --motion PATH".
/// @throws UsageError when `path` is empty.
void overrideMotion(ModelDocument& document, const std::string& path);

/// Replaces the model's `<reporter outputs="...">` patterns by `patterns` (COMPONENT.OUTPUT,
/// '*' any run of characters), e.g. to record a few outputs of a long run. Errors about them
/// name "command line: --report PATTERN". @throws UsageError for an empty pattern.
void overrideReporter(ModelDocument& document, const std::vector<std::string>& patterns);

}  // namespace rbfmuscle
