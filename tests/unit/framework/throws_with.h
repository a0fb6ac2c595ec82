// SPDX-License-Identifier: Apache-2.0
#pragma once
/// Asserts that a call throws FrameworkError whose message contains a text.
#include "framework/framework_error.h"

#include <gtest/gtest.h>

#include <functional>
#include <string>

namespace rbfmuscle::test {

inline ::testing::AssertionResult throwsWith(const std::function<void()>& f,
                                             const std::string& text) {
  try {
    f();
  } catch (const FrameworkError& error) {
    if (std::string(error.what()).find(text) != std::string::npos)
      return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "message '" << error.what() << "' lacks '" << text << "'";
  }
  return ::testing::AssertionFailure() << "no FrameworkError thrown";
}

}  // namespace rbfmuscle::test
