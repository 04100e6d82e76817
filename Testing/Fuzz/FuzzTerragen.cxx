// libFuzzer harness: terroir::io::ReadTerragen on arbitrary bytes (the Terragen reader's
// parser), then a write-read round trip of every file it accepts. Aborts (__builtin_trap)
// when an invariant breaks:
// - a rejected file leaves an empty terrain and exactly one line of error text;
// - an accepted one has nx, ny >= 2, nx*ny raw values and finite heights in metres;
// - WriteTerragen accepts what ReadTerragen returned (unless heights pass 1.6e11 m, where
//   int16 units of at most 1e7 m no longer reach), and reading that back gives the same
//   grid with heights within the writer's quantisation bound range / 131068 + dz / 65534 m.
#include "FuzzCheck.h"
#include "Terragen.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace
{
using terroir_fuzz::Check;
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  terroir::io::TerragenTerrain terrain;
  std::string error;
  if (!terroir::io::ReadTerragen(data, size, terrain, error))
  {
    Check(!error.empty() && error.find('\n') == std::string::npos);
    Check(terrain.nx == 0 && terrain.ny == 0 && terrain.heights.empty() && terrain.raw.empty());
    return 0;
  }
  Check(error.empty());
  Check(terrain.nx >= 2 && terrain.ny >= 2);
  const std::size_t count = static_cast<std::size_t>(terrain.nx) * terrain.ny;
  Check(terrain.heights.size() == count && terrain.raw.size() == count);
  // Every height byte came from the input: the file holds at least 2 bytes per height.
  Check(2 * count <= size);
  float lo = terrain.heights[0];
  float hi = lo;
  for (float h : terrain.heights)
  {
    Check(std::isfinite(h));
    lo = std::min(lo, h);
    hi = std::max(hi, h);
  }
  std::vector<std::uint8_t> bytes;
  std::string warning;
  if (!terroir::io::WriteTerragen(terrain.heights.data(),
        terrain.nx,
        terrain.ny,
        terrain.scale[0],
        terrain.scale[1],
        bytes,
        warning,
        error))
  {
    // Only heights beyond what int16 units of at most kTerragenMaxScale metres hold.
    Check(std::max(std::fabs(lo), std::fabs(hi)) >= 1.6e11f);
    Check(error.find("out of the range Terragen can store") != std::string::npos);
    return 0;
  }
  Check(warning.empty());
  terroir::io::TerragenTerrain again;
  Check(terroir::io::ReadTerragen(bytes, again, error));
  Check(again.nx == terrain.nx && again.ny == terrain.ny);
  // again.scale[2] is the vertical unit dz the writer chose.
  const double bound = (static_cast<double>(hi) - lo) / 131068.0 + again.scale[2] / 65534.0 +
    1e-6 * std::max(std::fabs(lo), std::fabs(hi)) + 1e-6;
  for (std::size_t k = 0; k < count; ++k)
  {
    Check(std::fabs(static_cast<double>(again.heights[k]) - terrain.heights[k]) <= bound);
  }
  return 0;
}
