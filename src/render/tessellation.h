#pragma once
/// Triangle meshes of the scene's shapes for drawing: the analytic obstacles (plane,
/// sphere, capsule, box, ellipsoid), obstacle meshes, tools and the intestine's skin. All
/// append to a TriMesh (so several shapes can share one upload), counter-clockwise seen
/// from outside, with outward unit normals.
#include <span>

#include <Eigen/Geometry>

#include "collision/obstacle.h"
#include "common/types.h"
#include "render/gpu_mesh.h"
#include "skin/mesh.h"

namespace viscera::render {

/// Ellipsoid `centre + rotation * diag(radii) * u` over the unit sphere u: `slices` around
/// the third axis, `stacks` from pole to pole. Normals are the exact surface normals.
/// @pre radii > 0, slices >= 3, stacks >= 2.
void AppendEllipsoid(const Vec3& centre, const Vec3& radii, const Eigen::Quaterniond& rotation,
                     int slices, int stacks, TriMesh* out);

/// Sphere (an ellipsoid with equal radii).
void AppendSphere(const Vec3& centre, double radius, int slices, int stacks, TriMesh* out);

/// Capsule: the points within `radius` of the segment a-b; `slices` around the axis, a
/// hemisphere of slices / 4 rings at each end. a == b gives a sphere.
void AppendCapsule(const Vec3& a, const Vec3& b, double radius, int slices, TriMesh* out);

/// Box of half extents `half` (m) in its own frame, rotated then centred: flat faces.
void AppendBox(const Vec3& centre, const Vec3& half, const Eigen::Quaterniond& rotation,
               TriMesh* out);

/// Square piece of the plane through `point` with unit `normal` (facing the free side),
/// `half_size` (m) each way from the projection of `around` onto the plane.
void AppendPlane(const Vec3& point, const Vec3& normal, const Vec3& around, double half_size,
                 TriMesh* out);

/// A ruled film between two polylines of equal length k >= 2 (the mesentery: from its root to
/// the bowel): quads (a_i, a_i+1, b_i+1, b_i) split in two, normals across the film (one side;
/// draw both faces). Texture space: (along_length i / (k - 1), 0 on a and across_length on b, 0),
/// in metres.
void AppendRuledFilm(std::span<const Vec3> a, std::span<const Vec3> b, double along_length,
                     double across_length, TriMesh* out);

/// Indexed triangles (#V by 3 vertices, #F by 3 faces) with smooth, area-weighted normals.
void AppendTriangles(const Points& vertices,
                     const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>& faces,
                     TriMesh* out);

/// Tessellation of one obstacle; the plane uses `around` and `plane_half_size`.
/// @throws InputError for a mesh obstacle without its mesh.
void AppendObstacle(const collision::Obstacle& obstacle, const Vec3& around, double plane_half_size,
                    TriMesh* out);

/// A laparoscopic grasper: the shaft capsule from `tip` back toward `port` (at least to the
/// port, `shaft_length` long), and two jaws at the tip, opened by `jaw` (0 closed .. 1
/// open, 35 degrees each) in the plane of `orientation`'s x axis and the shaft.
/// Nothing when the tip is at the port (a tool that never had a target).
void AppendTool(const Vec3& port, const Vec3& tip, const Eigen::Quaterniond& orientation,
                double jaw, double radius, double shaft_length, TriMesh* out);

/// The skin mesh converted to float (positions and normals; the skin's triangles are
/// already counter-clockwise from outside). Texture space: the tube of `length` and `radius`
/// (m) unrolled straight, (s length, radius cos angle, radius sin angle) from the skin's surface
/// coordinates, or the world positions for a skin without them (the implicit skin).
void AppendSkin(const skin::Mesh& mesh, double length, double radius, TriMesh* out);

}  // namespace viscera::render
