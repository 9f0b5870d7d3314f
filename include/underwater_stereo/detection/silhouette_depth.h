// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file A fitted object moved to the depth of its silhouette, when the two agree.

#include "underwater_stereo/common/stereo_calibration.h"
#include "underwater_stereo/detection/shape_fitter.h"

namespace underwater_stereo {

/// How far the silhouette may place an object from where its 3D points put it, in its own largest extent: a
/// surface lies within an extent of its centre, so a silhouette that asks for more was matched to another
/// outline (a neighbour's, or its own cut differently in the two frames). Chosen on the validation seeds
/// 60000-60299 (docs/accuracy.md, "The silhouette's depth checked against the points"; session 15, before the tube
/// rule of session 16): range error p95 of whole objects 17.6 % with no limit, 13.7 % at 1, 11.5 % at 0.75 and
/// 0.5, 12.8 % at 0.25; the median 1.26 % up to 0.75, 1.29 % at 0.5 and 1.82 % at 0.25.
constexpr double kMaxSilhouetteShiftInExtents = 0.75;

/// Moves `fit` along its viewing ray to the depth its silhouette's `disparity` [px] gives (the angular size
/// stays: centre and size scale together), the silhouette taken as the outline a sphere or tube of the fit's
/// pose would show (`cut_by_border`: the image border cuts the outline, so a tube shows at most one end). Stereo
/// surfaces are smoothed towards the object's rim, the silhouette is not. Left as it is, and false returned, when
/// the disparity is not finite and positive, the shape unknown, the centre not in front of the rectified camera,
/// or the move longer than kMaxSilhouetteShiftInExtents of the fit's largest size.
bool placeAtSilhouetteDepth(ShapeFit& fit, double disparity, const StereoCalibration& calibration,
                            bool cut_by_border = false);

}  // namespace underwater_stereo
