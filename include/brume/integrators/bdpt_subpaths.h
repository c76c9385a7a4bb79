// The two subpaths of a bidirectional sample: the camera subpath z0 (the pinhole) … and the
// light subpath y0 (a point on a light) …, each traced by randomWalk with its densities, and
// the light vertex y0 itself, which the light connection (s = 1) also makes from a fresh light
// sample.
#pragma once
#include "brume/guiding/guiding_field.h"
#include "brume/integrators/emitter_crossing.h"
#include "brume/integrators/mis.h"
#include "brume/integrators/path_vertex.h"

namespace brume {

class Sampler;
struct PathStats;

constexpr int kMaxSubpathVertices = 1024;  // per subpath; Russian roulette ends paths long before

// Light vertex on light `li` (picked with probability `pick`) at p, with surface normal n on
// the emitting side (zero for point, spot and directional lights) and emission position
// density pdfPos: its kind, texture coordinates, media (the side n faces), pdfFwd
// (pick·pdfPos; pick alone for a directional light, whose position density moves to y1)
// and beta = 1/pdfFwd.
PathVertex makeLightVertex(const Scene& scene, int li, float pick, Vec3 p, Vec3 n, float pdfPos);

// The camera subpath's first vertex alone, z0 (the pinhole), for strategies that connect
// light subpaths to the camera and nothing else (auto's partial pilot pass). Returns 1.
int cameraVertexOnly(const Scene& scene, float fx, float fy, int width, int height, PathVertex* path);

// Camera subpath through film position (fx, fy); at most maxScatter vertices past z0. From
// vertex passFrom on, and at passFirstAt after a vertex that is not specular, the walk passes
// through media (WalkStart). Returns the vertex count, z0 included. hero: the colour channel
// that drives free flight in coloured media (both subpaths of a sample share it). guide and
// pixelValue: guided directions and survival (WalkStart). crossings: the transparent
// emitters its rays cross (WalkStart; null: none wanted).
int traceCameraSubpath(const Scene& scene, float fx, float fy, int width, int height, int maxScatter, int passFrom,
                       int passFirstAt, int hero, const Sampler& sampler, PathVertex* path, PathStats& stats,
                       const GuidingField* guide = nullptr, float pixelValue = -1.0f,
                       MisHeuristic heuristic = MisHeuristic::Power, int volumeLightsUpTo = 0,
                       std::vector<CrossingVertex>* crossings = nullptr);

// Light subpath; 0 if no light can emit (or a directional light in an infinite medium, which
// reaches nothing). cameraGuide: the camera walk's guide, for the reverse densities (WalkStart).
int traceLightSubpath(const Scene& scene, int maxScatter, int hero, const Sampler& sampler, PathVertex* path,
                      PathStats& stats, const GuidingField* cameraGuide = nullptr);

}  // namespace brume
