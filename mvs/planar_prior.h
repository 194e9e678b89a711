// Planar prior for weakly textured and grazing regions (after ACMP, Xu and
// Tao 2020): the confident pixels of a view's plane map are triangulated in
// the image, and each triangle's plane through their three points is a
// candidate for the pixels inside it. A surface whose texture is too weak or
// too foreshortened for PatchMatch to find its plane from a random start
// (ground seen from standing height, a plain wall between textured parts)
// gets the plane its confident surroundings span.
#pragma once

#include <opencv2/core.hpp>

#include "mvs/patch_match.h"

namespace hos::mvs {

// Per pixel of a plane map, the plane of the triangle of confident pixels it
// lies in: depth along the camera z axis (0 = no triangle) and the unit
// normal in the camera frame, facing the camera.
struct PriorPlanes {
  cv::Mat depth;   // CV_32F
  cv::Mat normal;  // CV_32FC3
};

// Confident pixels are the lowest-cost pixel of each block of block_px x
// block_px pixels whose cost is at most confident_cost. Their Delaunay
// triangles give the priors, except a triangle that spans a depth
// discontinuity or a fold (a corner's own normal more than
// max_normal_deviation_deg from the triangle's plane) or whose plane the
// camera sees within 5 degrees of edge-on.
PriorPlanes planar_prior(const PlaneMap& planes,
                         double confident_cost,
                         int block_px = 8,
                         double max_normal_deviation_deg = 30.0);

}  // namespace hos::mvs
