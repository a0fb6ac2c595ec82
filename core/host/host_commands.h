// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// The `run` and `info` commands of the rbfmuscle host. The host only wires
/// the framework together; it names no component class.
#include "host/usage_error.h"

#include <string>
#include <vector>

namespace rbfmuscle {

/// `rbfmuscle run MODEL.xml -o OUTDIR [-L plugin]... [--set COMPONENT.PROPERTY=VALUE]...
///  [--motion FILE] [--frames-mesh] [--quiet]`.
/// @param args the arguments after "run". @return exit code.
int runCommand(const std::vector<std::string>& args);

/// `rbfmuscle info [-L plugin]... [CLASS]`. @param args the arguments after "info".
int infoCommand(const std::vector<std::string>& args);

/// Top-level usage text.
std::string usageText();

}  // namespace rbfmuscle
