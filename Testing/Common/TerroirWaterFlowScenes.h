// Scenes and measurements shared by the water-flow unit tests (TestWaterFlow.cxx,
// TestWaterFlowWarmStart.cxx). Header only and without VTK: the unit tests link only the cores.
#ifndef TerroirWaterFlowScenes_h
#define TerroirWaterFlowScenes_h

#include "WaterFlow.h"

#include <cstdlib>
#include <vector>

namespace terroir_test
{

/// A flat nx x ny terrain (heights 0, square cells of `spacing` metres) with the view the
/// simulation reads; Z(i, j) sets a height.
struct WaterFlowGrid
{
  int nx;
  int ny;
  std::vector<float> z;
  terroir::GridView<float> view;

  WaterFlowGrid(int nx_, int ny_, double spacing = 1.0)
    : nx(nx_)
    , ny(ny_)
    , z(static_cast<std::size_t>(nx_) * ny_, 0.0f)
  {
    view.data = z.data();
    view.nx = nx;
    view.ny = ny;
    view.dx = spacing;
    view.dy = spacing;
  }
  /// Copies point their view at their own heights.
  WaterFlowGrid(const WaterFlowGrid& o)
    : nx(o.nx)
    , ny(o.ny)
    , z(o.z)
    , view(o.view)
  {
    view.data = z.data();
  }
  WaterFlowGrid& operator=(const WaterFlowGrid&) = delete;
  float& Z(int i, int j) { return z[static_cast<std::size_t>(j) * nx + i]; }
};

/// The V valley: side slopes of 1 m per cell towards the thalweg (column c), the floor falling
/// 0.01 m per cell to the south. Writes the heights (metres) of nx x ny cells, row j = 0 in
/// the south, into `z` (at least nx * ny values).
inline void DrawVValley(float* z, int nx, int ny, int c)
{
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      z[static_cast<std::size_t>(j) * nx + i] =
        static_cast<float>(std::abs(i - c) * 1.0 + j * 0.01);
    }
  }
}

/// The discharge of every cell per iteration (m^3) over `window` more iterations of `sim`.
inline std::vector<double> DischargePerIteration(terroir::hydrology::WaterFlowSimulation& sim,
  int window)
{
  const std::size_t n = static_cast<std::size_t>(sim.Nx()) * static_cast<std::size_t>(sim.Ny());
  std::vector<double> q0(n), q1(n);
  sim.GetDischarge(q0.data());
  for (int k = 0; k < window; ++k)
  {
    sim.Step();
  }
  sim.GetDischarge(q1.data());
  for (std::size_t t = 0; t < n; ++t)
  {
    q1[t] = (q1[t] - q0[t]) / window;
  }
  return q1;
}

} // namespace terroir_test

#endif
