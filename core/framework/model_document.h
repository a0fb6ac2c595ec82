// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// The model XML file, parsed (tinyxml2) into plain structs; no component is
/// created here. Format (version 1):
///
///     <RBFMuscleModel version="1" name="hip_flexion">
///       <skeleton file="hip_r.urdf"/>                    <!-- exactly one; relative to this file;
///                                                             .urdf or .osim (OpenSim model) -->
///       <plugin file="librbfmuscle_plugin.so"/>         <!-- zero or more; see PluginLoader -->
///       <motion file="motions/hip_flexion_0_80.mot"/>   <!-- exactly one; relative to this file -->
///       <components>                                    <!-- optional; updated in this order -->
///         <BodyOriginReporter name="femur_origin">      <!-- element = registered class -->
///           <point_mm>0 -400 0</point_mm>               <!-- property (snake_case) -->
///           <socket_body>femur_r</socket_body>          <!-- socket_NAME = target name -->
///           <filter><order>2</order></filter>           <!-- subcomponent: its properties -->
///         </BodyOriginReporter>
///       </components>
///       <reporter outputs="femur_origin.*"/>            <!-- optional; patterns, default "*" -->
///     </RBFMuscleModel>
///
/// The skeleton element may set the rest pose, where the scene's meshes were segmented
/// (components take it as their reference; a motion gives the coordinates it does not mention
/// their rest values):
///   rest_pose="default"           the coordinates' default values (URDF: all 0); the default
///   rest_pose="bodies_at_ground"  the coordinates that put every body frame at ground, for a
///                                 model whose bodies are all given in one image frame (the LHDL
///                                 OpenSim model: the CT frame), Skeleton::solveBodiesAtGround
#include "framework/framework_error.h"

#include <string>
#include <vector>

namespace rbfmuscle {

/// Largest model file read (bytes): 16 MiB, far above any scene (a few kB).
inline constexpr unsigned long long kMaxModelFileBytes = 16ull << 20;

/// Model file format version this build reads.
inline constexpr int kModelFileVersion = 1;

/// A `<propname>text</propname>` child of a component element.
struct PropertySpec {
  std::string name;
  std::string text;
  SourceLocation location;
};

/// A `<socket_NAME>target</socket_NAME>` child; `name` without the prefix.
struct SocketSpec {
  std::string name;
  std::string target;
  SourceLocation location;
};

/// One element inside `<components>`, or a subcomponent's element inside its owner's.
struct ComponentSpec {
  std::string class_name;  ///< element name (a subcomponent: its name)
  std::string name;        ///< `name` attribute (a subcomponent: its element name)
  SourceLocation location;
  std::vector<PropertySpec> properties;
  std::vector<SocketSpec> sockets;
  /// Child elements that hold elements: subcomponents (`<fibres><count>50</count></fibres>`).
  std::vector<ComponentSpec> subcomponents;
};

/// A `file` attribute of skeleton, plugin or motion.
struct FileReference {
  std::string as_written;  ///< attribute text
  std::string path;        ///< resolved against the model directory (plugins: as written)
  SourceLocation location;
};

/// `rest_pose` of the skeleton element.
enum class RestPose { kDefault, kBodiesAtGround };

struct ModelDocument {
  std::string path;       ///< model file as given
  std::string directory;  ///< absolute directory of the model file
  std::string name;       ///< `name` attribute of the root (default: file stem)
  int version = 0;
  FileReference skeleton;
  RestPose skeleton_rest_pose = RestPose::kDefault;
  std::vector<FileReference> plugins;
  FileReference motion;
  std::vector<ComponentSpec> components;
  /// Output selection patterns `COMPONENT.OUTPUT`, '*' matches any run of characters.
  std::vector<std::string> reporter_patterns{"*"};
  SourceLocation reporter_location;
};

/// Reads and checks the structure of a model file.
/// @throws FrameworkError naming the file, line and element: unreadable file or one
///   that is not a regular file (a device, FIFO or directory is refused before it is read),
///   a file over kMaxModelFileBytes,
///   XML syntax error, wrong root, missing or unsupported `version`, unknown
///   element or attribute, missing `file`/`name` attribute, duplicate or
///   invalid component name, duplicate property or socket.
ModelDocument readModelDocument(const std::string& path);

/// Same, from text; `path` is used for messages and relative paths.
ModelDocument parseModelDocument(const std::string& xml_text, const std::string& path);

}  // namespace rbfmuscle
