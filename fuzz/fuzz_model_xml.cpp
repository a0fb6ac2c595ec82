// SPDX-License-Identifier: Apache-2.0
// Fuzz target: model XML files (the document structure) and the text of every property in them,
// read as each property type a component can declare.
#include <Eigen/Core>

#include <string>

#include "framework/framework_error.h"
#include "framework/model_document.h"
#include "framework/property.h"
#include "fuzz_support.h"

namespace {

/// Parses `text` as a T; a refusal is a FrameworkError.
template <class T>
void tryParse(const std::string& text) {
  T value{};
  try {
    rbfmuscle::parsePropertyText(text, value);
  } catch (const rbfmuscle::FrameworkError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rbfmuscle;
  try {
    const ModelDocument document = parseModelDocument(fuzz::asText(data, size), "/fuzz/model.xml");
    for (const ComponentSpec& component : document.components)
      for (const PropertySpec& property : component.properties) {
        tryParse<double>(property.text);
        tryParse<int>(property.text);
        tryParse<bool>(property.text);
        tryParse<std::string>(property.text);
        tryParse<Eigen::Vector3d>(property.text);
      }
  } catch (const FrameworkError&) {
  }
  return 0;
}
