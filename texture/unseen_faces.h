// Colours of the faces no photo sees (the underside of an object on a
// turntable, a hidden back). They get a flat colour each; by default one
// diffused over the surface from the seen faces around them, so a hole in
// the photos' coverage takes the colour of the surface that borders it and
// never the background the face happens to project onto.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "texture/atlas.h"
#include "texture/charts.h"
#include "texture/mesh_topology.h"
#include "texture/seam_leveling.h"
#include "texture/texture_options.h"
#include "texture/texture_view.h"
#include "texture/visibility.h"

namespace hos::texture {

// Neutral colour of unseen faces with texture.unseen=grey, and of unseen
// pieces that border no seen face (8-bit RGB).
inline constexpr float kUnseenGrey = 128.0f;

// The colour of every seen face from its own view: the mean colour of the
// face's visible pixels in the view view selection chose (candidates, after
// exposure gains), plus the seam-leveling offset of its chart, averaged over
// its corners. #F; faces with labels -1 keep zero.
std::vector<Eigen::Vector3f> seen_face_colours(const FaceViewCandidates& candidates,
                                               const std::vector<int>& labels,
                                               const std::vector<Chart>& charts,
                                               const SeamLeveling& leveling);

// The background colour of every view whose photo has a uniform one (RGB,
// 8-bit scale, times the view's gain): the median of the pixels along a
// rectangle just inside the photo's border when at least kUniformBorderShare of them lie within
// kBackgroundDistance of it (an object photographed against a plain
// backdrop); nullopt otherwise (a scene fills the frame). #views.
std::vector<std::optional<Eigen::Vector3f>> uniform_backgrounds(const std::vector<TextureView>& views,
                                                                const std::vector<Eigen::Vector3f>& gains);
inline constexpr double kUniformBorderShare = 0.7;
inline constexpr float kBackgroundDistance = 24.0f;  // 8-bit RGB distance

// Colours of faces with labels -1, from the colours of the seen faces
// (seen_face_colours) by mode (texture.unseen):
// - kDiffuse: a harmonic fill over edge-adjacent faces: each unseen face is
//   the mean of its neighbours, the sources fixed. Sources are the seen
//   faces except those viewed at grazing angles (cos_angle of their view
//   below kMinSourceCosine: their pixels lie along the silhouette) and those
//   whose colour is their view's background (backgrounds, from
//   uniform_backgrounds; the surface reaches past the object there); these
//   are filled like unseen ones. The sources bordering the fill take the
//   median colour of the sources around them.
// - kGrey: kUnseenGrey; kMark: magenta, to show where the photos do not reach.
std::vector<FlatFace> colour_unseen_faces(const MeshTopology& topology,
                                          const FaceViewCandidates& candidates,
                                          const std::vector<int>& labels,
                                          const std::vector<Eigen::Vector3f>& seen_colours,
                                          const std::vector<std::optional<Eigen::Vector3f>>& backgrounds,
                                          UnseenFaces mode);

// What the faces become by mode, for messages ("grey").
const char* unseen_faces_description(UnseenFaces mode);

// Faces seen closer to edge-on than this (cosine of the angle between normal
// and viewing ray) are no source of the diffusion (75 degrees).
inline constexpr float kMinSourceCosine = 0.26f;

}  // namespace hos::texture
