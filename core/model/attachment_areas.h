// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// A muscle's attachment areas: the measured patches of bone it starts from
/// (origin) and ends on (insertion), as clouds of points in the ground (CT)
/// frame, millimetres. Read from a JSON landmark file or written inline in a
/// model property.
///
/// The JSON file (for example models/hip/landmarks/attachment_areas.json):
///
///     {"units": "mm",
///      "frame": "...",                       (free text, not read)
///      "clouds": {"NAME": [{"name": "1", "mm": [x, y, z]}, ...], ...}}
///
/// Each point is an object whose "mm" member holds 3 finite numbers (mm); its
/// "name" (optional) only labels it in error messages. Other members are ignored.
#include <Eigen/Core>

#include <string>
#include <vector>

#include "model/model_error.h"

namespace rbfmuscle {

/// One attachment area: a named cloud of points on a bone.
struct AttachmentArea {
  std::string name;            ///< cloud name in the file, or "inline"
  Eigen::Matrix3Xd points_mm;  ///< one column per point; ground (CT) frame, mm
};

/// Largest attachment areas file read (bytes): 64 MiB, far above any
/// landmark file; a bigger file is refused before it is read.
constexpr long long kMaxAttachmentAreasFileBytes = 64LL * 1024 * 1024;

/// Largest plausible coordinate magnitude (mm): 1e5 mm = 100 m. A larger
/// value means wrong units or a corrupt file.
constexpr double kMaxAttachmentCoordinateMm = 1e5;

/// Reads the clouds named `cloud_names` from the JSON file `json_path`, in the
/// order asked (each name at most once; an empty list reads nothing but still
/// checks the file).
/// @throws ModelError naming the file (and the cloud and the 1-based point
/// where relevant) for: a missing file or one that is not a regular file; a
/// file larger than kMaxAttachmentAreasFileBytes; text that is not JSON (line,
/// column and byte of the fault); "units" other than "mm"; no "clouds" object;
/// a cloud defined twice; a name asked twice; a name not in the file (the
/// available names are listed, sorted, or the 10 closest when there are more
/// than 20, with a near miss or the names containing it suggested); a cloud
/// that is not an array or is empty; a point that is not 3 finite numbers; a
/// coordinate of magnitude above kMaxAttachmentCoordinateMm.
std::vector<AttachmentArea> readAttachmentAreas(const std::string& json_path,
                                                const std::vector<std::string>& cloud_names);

/// Reads the attachment areas that a model property names, in one of two forms
/// (white space, line breaks included, is free around every token):
///
///     spec      := file_ref | inline
///     file_ref  := FILE ":" NAME ("," NAME)*
///     inline    := point (";" point)* [";"]
///     point     := NUMBER NUMBER NUMBER           (x y z, mm, ground frame)
///
/// A spec that contains ':' is a file reference: FILE is the text before the
/// first ':' (it cannot itself contain ':'), relative to `base_directory`
/// unless absolute; each NAME is a cloud of that file (it cannot contain ','),
/// read with readAttachmentAreas in the order written. Otherwise the spec is
/// inline points, returned as one area named "inline"; NUMBER is a decimal
/// number as strtod reads it and must be finite with magnitude at most
/// kMaxAttachmentCoordinateMm.
///
/// Examples: `landmarks/attachment_areas.json: LC_SET_Ori_1_R_M081_Glut_Max,
/// LC_SET_Ori_2_R_M081_Glut_Max` and `120 190 -340; 121.5 196 -341`.
/// @throws ModelError quoting the spec for an empty spec, an empty FILE or
/// NAME, or an inline point that is not 3 finite, plausible numbers (1-based
/// point index); and every error of readAttachmentAreas.
std::vector<AttachmentArea> parseAttachmentAreaSpec(const std::string& spec,
                                                    const std::string& base_directory);

/// The points of `areas`, in order, as one matrix (3×K, the areas' frame and unit).
Eigen::Matrix3Xd joinAreas(const std::vector<AttachmentArea>& areas);

}  // namespace rbfmuscle
