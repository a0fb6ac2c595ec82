// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// A built model: skeleton (URDF), motion, and configured components with
/// connected sockets, built from a ModelDocument and a Registry.
#include "framework/component.h"
#include "framework/model_document.h"
#include "framework/registry.h"
#include "model/motion.h"
#include "model/skeleton.h"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace rbfmuscle {

/// Creates each component of the document (Registry::create), reads its
/// properties and socket targets, and finalizes its properties. Needs no
/// skeleton. @throws FrameworkError naming file, line and element: unknown
/// class (listing the registered ones), unknown property or socket (listing
/// the class's), badly typed value, missing required property, out-of-range value.
std::vector<std::unique_ptr<Component>> createComponents(const ModelDocument& document,
                                                         const Registry& registry);

/// Hears each component's initialisation: before it starts (`done` false) and after it
/// finished (`done` true); `index` is 0-based of `count`.
using InitProgressFn = std::function<void(const Component& component, int index, int count, bool done)>;

class Model {
 public:
  /// Loads the skeleton and motion, creates the components and connects
  /// their sockets (bodies by skeleton body name, components by name).
  /// @throws FrameworkError with the XML location: bad component (see
  ///   createComponents), missing/bad URDF or motion (the ModelError text,
  ///   e.g. a motion column naming an unknown coordinate), unknown socket target.
  static Model build(ModelDocument document, const Registry& registry);

  Model(Model&&) noexcept = default;
  Model& operator=(Model&&) noexcept = default;

  const ModelDocument& getDocument() const { return document_; }
  const Skeleton& getSkeleton() const { return skeleton_; }
  Skeleton& updSkeleton() { return skeleton_; }
  const Motion& getMotion() const { return motion_; }
  /// Components in document order (= update order).
  const std::vector<std::unique_ptr<Component>>& getComponents() const { return components_; }

  /// Calls Component::initialize on each component in order; errors are
  /// prefixed with the component's XML location. Checks for an interruption
  /// (throwIfInterrupted, interrupt.h) before each component.
  /// @param output_directory where components may write files (see InitContext)
  /// @param progress hears each component start and finish (may be empty)
  void initializeComponents(const std::string& output_directory, const InitProgressFn& progress = {});

 private:
  Model(ModelDocument document, Skeleton skeleton, Motion motion,
        std::vector<std::unique_ptr<Component>> components);

  ModelDocument document_;
  Skeleton skeleton_;
  Motion motion_;
  std::vector<std::unique_ptr<Component>> components_;
};

}  // namespace rbfmuscle
