// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Sockets: named references from a component to a skeleton body or to
/// another component, declared as members (as OpenSim's
/// OpenSim_DECLARE_SOCKET) and connected by name from `<socket_NAME>` XML
/// elements. Bodies are always sockets, never name strings.
///
///     BodySocket body{this, "body", "body whose origin is reported"};
///     BodyListSocket obstacles{this, "obstacles", "bones the muscle may not enter"};
///     ComponentSocket<RBFMuscle> muscle{this, "muscle", "RBFMuscle", "muscle to read"};
#include <string>
#include <vector>

namespace rbfmuscle {

class Component;

/// What a socket may connect to: the skeleton's bodies and the model's
/// components, by name.
class ConnectionTargets {
 public:
  ConnectionTargets(std::vector<std::string> body_names, std::vector<Component*> components);
  /// Index into the body names (= Skeleton body index), or -1.
  int findBody(const std::string& name) const;
  /// The component of that name, or nullptr.
  Component* findComponent(const std::string& name) const;
  /// "pelvis, femur_r" for error messages.
  std::string listBodies() const;
  std::string listComponents() const;

 private:
  std::vector<std::string> body_names_;
  std::vector<Component*> components_;
};

/// Type-erased socket: name, kind, target name; connection by name.
class AbstractSocket {
 public:
  AbstractSocket(const AbstractSocket&) = delete;
  AbstractSocket& operator=(const AbstractSocket&) = delete;
  virtual ~AbstractSocket() = default;

  const std::string& getName() const { return name_; }
  const std::string& getDescription() const { return description_; }
  /// What it connects to, for `info`: "body", "list of bodies", "component RBFMuscle".
  virtual std::string getKind() const = 0;
  /// Target name(s) as read from `<socket_NAME>` (space-separated for a list).
  const std::string& getTargetName() const { return target_; }
  void setTargetName(std::string target) { target_ = std::move(target); }
  bool isConnected() const { return connected_; }

  /// Resolves the target name. @throws FrameworkError "socket 'NAME': ..."
  /// naming the missing target and listing the candidates.
  void connect(const ConnectionTargets& targets);

 protected:
  AbstractSocket(Component* owner, std::string name, std::string description);
  /// Resolves target_ (non-empty); throws FrameworkError without the prefix.
  virtual void resolve(const ConnectionTargets& targets) = 0;

 private:
  std::string name_;
  std::string description_;
  std::string target_;
  bool connected_ = false;
};

/// Socket to one skeleton body; gives its index into FrameState body poses.
class BodySocket final : public AbstractSocket {
 public:
  BodySocket(Component* owner, std::string name, std::string description)
      : AbstractSocket(owner, std::move(name), std::move(description)) {}
  std::string getKind() const override { return "body"; }
  /// Skeleton body index (valid once connected).
  int getBodyIndex() const { return body_index_; }

 private:
  void resolve(const ConnectionTargets& targets) override;
  int body_index_ = -1;
};

/// Socket to one or more skeleton bodies (`<socket_NAME>pelvis femur_r</socket_NAME>`).
class BodyListSocket final : public AbstractSocket {
 public:
  BodyListSocket(Component* owner, std::string name, std::string description)
      : AbstractSocket(owner, std::move(name), std::move(description)) {}
  std::string getKind() const override { return "list of bodies"; }
  /// Skeleton body indices in the order given (valid once connected).
  const std::vector<int>& getBodyIndices() const { return body_indices_; }

 private:
  void resolve(const ConnectionTargets& targets) override;
  std::vector<int> body_indices_;
};

/// Socket to another component of class T (checked with dynamic_cast).
template <class T>
class ComponentSocket final : public AbstractSocket {
 public:
  /// @param type_name the class name T registers under, for messages and `info`.
  ComponentSocket(Component* owner, std::string name, std::string type_name,
                  std::string description)
      : AbstractSocket(owner, std::move(name), std::move(description)),
        type_name_(std::move(type_name)) {}
  std::string getKind() const override { return "component " + type_name_; }
  /// The connected component (valid once connected).
  const T& get() const { return *target_; }
  T& upd() const { return *target_; }

 private:
  void resolve(const ConnectionTargets& targets) override;
  std::string type_name_;
  T* target_ = nullptr;
};

/// Throws FrameworkError for a component target that is missing or of the wrong class.
[[noreturn]] void throwBadComponentTarget(const ConnectionTargets& targets,
                                          const std::string& target,
                                          const std::string& type_name, bool exists);

template <class T>
void ComponentSocket<T>::resolve(const ConnectionTargets& targets) {
  Component* found = targets.findComponent(getTargetName());
  target_ = dynamic_cast<T*>(found);
  if (target_ == nullptr)
    throwBadComponentTarget(targets, getTargetName(), type_name_, found != nullptr);
}

}  // namespace rbfmuscle
