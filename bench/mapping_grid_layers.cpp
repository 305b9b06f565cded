// The 2D map layers and the 2D ESDF for one frame: eLabrador's 10 m x 10 m window at 0.1 m built
// from about 20k voxels (a labelled street: sidewalk and road ground, a kerb, building walls,
// poles, parked cars, people, a tree), then the distance transform's two backends side by side.
// Budget: the whole mapping step is 25 ms median per frame on the 2-core machine; the 2D maps and
// ESDF should be a small part of it. OpenCV runs on one thread, like dynamicEDT3D.
#include <benchmark/benchmark.h>
#include <dynamicEDT3D/dynamicEDT3D.h>

#include <chrono>
#include <opencv2/core.hpp>
#include <random>

#include "navaid/mapping/cost_map.hpp"
#include "navaid/mapping/esdf_2d.hpp"

namespace {

using namespace navaid;
using namespace navaid::mapping;

constexpr double kCamera = 1.5;
constexpr double kSigmaXy = 0.1;

const bool kOneThread = [] {
  cv::setNumThreads(1);
  return true;
}();

void add_box(MapVoxels& out, const Vec3& lo, const Vec3& hi, SemanticClass c, double r = 0.1) {
  for (double z = lo.z() + r / 2; z < hi.z(); z += r) {
    for (double y = lo.y() + r / 2; y < hi.y(); y += r) {
      for (double x = lo.x() + r / 2; x < hi.x(); x += r) {
        MapVoxel v;
        v.center_W = Vec3(x, y, z);
        v.size_m = r;
        v.occupancy = 0.9;
        v.semantic = c;
        v.class_probability = 0.8;
        out.push_back(v);
      }
    }
  }
}

// Surfaces only, as a depth camera sees them: ground layer, walls and objects as shells.
MapVoxels street_scene() {
  using S = SemanticClass;
  MapVoxels v;
  add_box(v, Vec3(-5, -5, -0.1), Vec3(5, 1, 0), S::kSidewalk);
  add_box(v, Vec3(-5, 1.15, -0.1), Vec3(5, 5, 0), S::kRoad);
  add_box(v, Vec3(-5, 1, -0.1), Vec3(5, 1.15, 0.15), S::kCurb);
  add_box(v, Vec3(-5, -5, 0), Vec3(5, -4.8, 3.0), S::kBuilding);     // facade, up past the window
  add_box(v, Vec3(-5, -4.8, 0), Vec3(-4.8, 0.5, 2.5), S::kWall);
  for (double x = -4; x < 5; x += 2.0) add_box(v, Vec3(x, 0.6, 0), Vec3(x + 0.1, 0.7, 2.5), S::kPole);
  add_box(v, Vec3(-3, 1.6, 0), Vec3(1.5, 1.7, 1.4), S::kCar);         // parked car, street side
  add_box(v, Vec3(-3, 1.6, 1.3), Vec3(1.5, 3.4, 1.4), S::kCar);       // its roof
  add_box(v, Vec3(2, -2, 0), Vec3(2.3, -1.8, 1.8), S::kPerson);
  add_box(v, Vec3(-1, -3, 0), Vec3(-0.8, -2.8, 2.0), S::kTreeTrunk);
  add_box(v, Vec3(-2, -4, 2.0), Vec3(0.2, -1.8, 2.3), S::kVegetation);  // canopy over the sidewalk
  add_box(v, Vec3(3, -4.5, 0), Vec3(4.5, -4.0, 0.5), S::kBench);
  return v;
}

struct Frame {
  MapVoxels voxels = street_scene();
  GridGeometry geometry = GridGeometry::around(Vec2(0.03, -0.02), GridConfig{});
};

void BM_AllLayersAndEsdf(benchmark::State& state) {
  const Frame f;
  const auto backend = static_cast<DistanceTransformBackend>(state.range(0));
  Esdf2d esdf(Esdf2dConfig{backend});
  for (auto _ : state) {
    const HeightMap h = build_height_map(f.voxels, f.geometry, kCamera, HeightMapConfig{});
    const UndulationMap u = build_undulation_map(h, UndulationConfig{});
    const CollisionMap c = build_collision_map(f.voxels, f.geometry, kCamera, CollisionConfig{});
    const CostMap m = build_cost_map(c, u, kSigmaXy, CostMapConfig{});
    esdf.update(m);
    benchmark::DoNotOptimize(esdf.field().cells().data());
  }
  state.SetLabel(to_string(backend));
  state.counters["voxels"] = static_cast<double>(f.voxels.size());
}
BENCHMARK(BM_AllLayersAndEsdf)
    ->Arg(static_cast<int>(DistanceTransformBackend::kOpenCv))
    ->Arg(static_cast<int>(DistanceTransformBackend::kDynamicEdt))
    ->Unit(benchmark::kMillisecond);

// One layer at a time, for the breakdown.
void BM_HeightMap(benchmark::State& state) {
  const Frame f;
  for (auto _ : state) benchmark::DoNotOptimize(build_height_map(f.voxels, f.geometry, kCamera, HeightMapConfig{}));
}
BENCHMARK(BM_HeightMap)->Unit(benchmark::kMicrosecond);

void BM_UndulationMap(benchmark::State& state) {
  const Frame f;
  const HeightMap h = build_height_map(f.voxels, f.geometry, kCamera, HeightMapConfig{});
  for (auto _ : state) benchmark::DoNotOptimize(build_undulation_map(h, UndulationConfig{}));
}
BENCHMARK(BM_UndulationMap)->Unit(benchmark::kMicrosecond);

void BM_CollisionMap(benchmark::State& state) {
  const Frame f;
  for (auto _ : state) {
    benchmark::DoNotOptimize(build_collision_map(f.voxels, f.geometry, kCamera, CollisionConfig{}));
  }
}
BENCHMARK(BM_CollisionMap)->Unit(benchmark::kMicrosecond);

void BM_CostMapWithInflation(benchmark::State& state) {
  const Frame f;
  const HeightMap h = build_height_map(f.voxels, f.geometry, kCamera, HeightMapConfig{});
  const UndulationMap u = build_undulation_map(h, UndulationConfig{});
  const CollisionMap c = build_collision_map(f.voxels, f.geometry, kCamera, CollisionConfig{});
  for (auto _ : state) benchmark::DoNotOptimize(build_cost_map(c, u, kSigmaXy, CostMapConfig{}));
}
BENCHMARK(BM_CostMapWithInflation)->Unit(benchmark::kMicrosecond);

// The ESDF's obstacle mask of the street frame, and a random one with 10 % obstacles.
ImageU8 street_mask() {
  const Frame f;
  const HeightMap h = build_height_map(f.voxels, f.geometry, kCamera, HeightMapConfig{});
  const CostMap m = build_cost_map(build_collision_map(f.voxels, f.geometry, kCamera, CollisionConfig{}),
                                   build_undulation_map(h, UndulationConfig{}), kSigmaXy, CostMapConfig{});
  ImageU8 mask(f.geometry.width(), f.geometry.height(), 1, 0);
  for (int y = 0; y < mask.height; ++y) {
    for (int x = 0; x < mask.width; ++x) mask.at(x, y) = m.is_obstacle(x, y) ? 1 : 0;
  }
  return mask;
}

ImageU8 random_mask(int size) {
  std::mt19937 rng(7);
  std::bernoulli_distribution set(0.1);
  ImageU8 mask(size, size, 1, 0);
  for (auto& v : mask.pixels) v = set(rng) ? 1 : 0;
  return mask;
}

// Both backends on the same mask, alternating, timed by hand: the ratio is the counter.
void BM_DistanceTransformRatio(benchmark::State& state) {
  const ImageU8 mask = state.range(0) == 0 ? street_mask() : random_mask(static_cast<int>(state.range(0)));
  ImageF32 out;
  double opencv_s = 0.0, dynamic_s = 0.0;
  using Clock = std::chrono::steady_clock;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    distance_transform(mask, DistanceTransformBackend::kOpenCv, out);
    benchmark::DoNotOptimize(out.data());
    const auto t1 = Clock::now();
    distance_transform(mask, DistanceTransformBackend::kDynamicEdt, out);
    benchmark::DoNotOptimize(out.data());
    const auto t2 = Clock::now();
    opencv_s += std::chrono::duration<double>(t1 - t0).count();
    dynamic_s += std::chrono::duration<double>(t2 - t1).count();
  }
  const auto n = static_cast<double>(state.iterations());
  state.counters["opencv_us"] = 1e6 * opencv_s / n;
  state.counters["dynamicedt3d_us"] = 1e6 * dynamic_s / n;
  state.counters["dynamicedt3d_over_opencv"] = dynamic_s / opencv_s;
  state.SetLabel(state.range(0) == 0 ? "street 100x100" : "random 10%");
}
BENCHMARK(BM_DistanceTransformRatio)->Arg(0)->Arg(100)->Arg(400)->Unit(benchmark::kMicrosecond);

// dynamicEDT3D's own strength, for fairness: a kept map where a few cells change (a person of 3 x 3
// cells steps one cell), updated incrementally. It applies only while the window stands still: a
// scrolled window moves every cell's index, and the map must be rebuilt.
void BM_DynamicEdtIncremental(benchmark::State& state) {
  const ImageU8 mask = street_mask();
  DynamicEDT3D edt(mask.width * mask.width + mask.height * mask.height + 1);
  edt.initializeEmpty(mask.width, mask.height, 1, true);
  for (int y = 0; y < mask.height; ++y) {
    for (int x = 0; x < mask.width; ++x) {
      if (mask.at(x, y) != 0) edt.occupyCell(x, y, 0);
    }
  }
  edt.update(true);
  int step = 0;
  for (auto _ : state) {
    const int from = 30 + (step % 2), to = 31 - (step % 2);
    for (int dy = 0; dy < 3; ++dy) {
      for (int dx = 0; dx < 3; ++dx) edt.clearCell(from + dx, 60 + dy, 0);
    }
    for (int dy = 0; dy < 3; ++dy) {
      for (int dx = 0; dx < 3; ++dx) edt.occupyCell(to + dx, 60 + dy, 0);
    }
    edt.update(true);
    benchmark::DoNotOptimize(edt.getDistance(50, 50, 0));
    ++step;
  }
}
BENCHMARK(BM_DynamicEdtIncremental)->Unit(benchmark::kMicrosecond);

}  // namespace
