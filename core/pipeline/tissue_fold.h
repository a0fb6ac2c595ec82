// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Tissue a bone has taken, folded back out of it rather than cut away.
///
/// The muscle is {min(f, s) > 0}: where the tissue map carries part of a muscle into a bone, the
/// bone cuts it, and a thin part (a tendon lying on a bone) can be cut through. Folding reflects
/// what a bone took in its face: outside a bone, at distance s from it, the muscle is also where
/// the field is inside the bone at depth s straight below,
///   f̃(y) = max(f(y), min(f(m), f(q), cap)),  q = y − s ∇s (the foot on the bone's face),
///   m = y − 2 s ∇s (the mirror image inside it),
/// for each bone near y (BoneClearance::visitFolds gives m, q and the cap). The foot term keeps
/// only tissue that reaches the bone's face: a part of the field lying wholly inside a bone (a
/// fit's lobe behind an attachment) stays hidden. A layer pressed into a bone thus comes out on
/// its face as thick as it went in (up to the bone's band), and the volume step has that much
/// less to give back elsewhere. The volume measure and the pieces count use f̃; the fibres and
/// the tracked surface keep to min(f, s) ≤ min(f̃, s) (MuscleShape's BoneContact). At rest
/// f̃ > 0 only where the field overlaps a bone more deeply than the muscle lies on it outside.
/// f̃ is continuous; its gradient is that of the winning term, for a flat face.
#include "collision/bone_clearance.h"
#include "rbf/deformed_field.h"

namespace rbfmuscle {

/// f̃ at y (M, mm) given f there (value and gradient): the field with the tissue the bones have
/// taken folded out of them (file comment). Evaluates the whole field at the folds.
FieldSample foldOutOfBones(const DeformedField& field, const BoneClearance& bones, const Eigen::Vector3d& y_mm,
                           const FieldSample& f);

}  // namespace rbfmuscle
