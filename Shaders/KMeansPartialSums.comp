// KMeansPartialSums.comp: step 2 of a Lloyd iteration (per-cluster sums, counts, inertia) for
// the cells of one chunk; mirrors terroir::clustering::KMeansBlockSums and the block-order total
// of KMeansCPUEngine::Sums (Filters/Clustering/Core/KMeans.{h,cxx}), bit for bit.
// Double precision, like WaterFlow.comp: the core sums in double, and the centres must be the
// CPU's bits.
//
// Two entry points, chosen by a define:
//
// (default) block pass: one invocation per (block b of the chunk, group g), g = 0..G-1 with
//   G = ceil(F / 4) + 1: group g < G - 1 sums features 4g .. 4g + 3 (those < F; the four
//   accumulators are the components of a dvec4), group G - 1 counts the members (as doubles,
//   exact) and sums the inertia. The invocation walks the block's cells (KMeansBlockCells =
//   uBlockCells, fewer in the last block of the data) in cell order with one accumulator per
//   cluster, starting from 0: acc[label(c)] += double(x_fc) (counter: += 1, and inertia +=
//   double(d2(c)) over every cell), exactly the additions of KMeansBlockSums in the same order
//   (the accumulator of the current run of equal labels is kept in a register, as the core's
//   GroupSums does). It writes record b of `partials`: R = (F + 1) * K + 1 doubles,
//   [f * K + k] = sum of feature f over cluster k, [F * K + k] = count of cluster k,
//   [(F + 1) * K] = inertia. Invocation i = b * G + g, so neighbouring invocations share a block
//   (and its labels).
//
// KMEANS_FINAL_PASS: one invocation per record entry i = 0..R-1 adds the chunk's blocks in
//   block order to the running total: acc = totals[i]; acc += partials[b * R + i] for
//   b = 0..uBlocks-1; totals[i] = acc. `totals` is zeroed before the first chunk (0 + x = x
//   exactly) and chunks are reduced in order, so totals are the block-order sums over all
//   blocks, as KMeansCPUEngine::Sums adds them.
//
// Bindings (std430; n = uCells cells of the chunk, F = uFeatures, K = uK, B = uBlocks blocks
// of the chunk, R = (F + 1) * K + 1):
//   0  readonly  float  features[F*n]   block pass: feature f of cell c at f * n + c
//   1  readonly  int    labels[n]       block pass: labels 0..K-1 (KMeansAssign.comp)
//   2  readonly  float  distances[n]    block pass: d2 of each cell to its own centre
//   3            double partials[B*R]   block pass writes, final pass reads
//   4            double totals[R]       final pass: read and written (running totals);
//                                       host layout: sums[k * F + f] = totals[f * K + k],
//                                       counts[k] = totals[F * K + k], inertia = totals[R - 1]
//   5            dvec4  scratch[]       block pass: MAX_K accumulators per invocation
//                                       (invocation i's at i * MAX_K), written before read;
//                                       a buffer, not a local array: NVIDIA's compiler (driver
//                                       580.159.04) returned other values than those stored
//                                       in local arrays of doubles
// Uniforms: uint uCells (n), int uFeatures (F >= 1), int uK (1..MAX_K), uint uBlocks (B),
// uint uBlockCells (KMeansBlockCells).
// Defines: LOCAL_X (work group, 64 by default); MAX_K (accumulators per invocation, >= uK,
// KMeansMaxClusters = 64 by default; the host passes K rounded up to a power of two);
// KMEANS_FINAL_PASS (the final pass). Dispatch ceil(B * G / LOCAL_X) groups (block pass) or
// ceil(R / LOCAL_X) groups (final pass), 1-D.

#ifndef LOCAL_X
#define LOCAL_X 64
#endif
#ifndef MAX_K
#define MAX_K 64
#endif

layout(local_size_x = LOCAL_X, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer FeatureBuffer { float features[]; };
layout(std430, binding = 1) readonly buffer LabelBuffer { int labels[]; };
layout(std430, binding = 2) readonly buffer DistanceBuffer { float distances[]; };
layout(std430, binding = 3) buffer PartialBuffer { double partials[]; };
layout(std430, binding = 4) buffer TotalBuffer { double totals[]; };
layout(std430, binding = 5) buffer ScratchBuffer { dvec4 scratch[]; };

uniform uint uCells;
uniform int uFeatures;
uniform int uK;
uniform uint uBlocks;
uniform uint uBlockCells;

#ifdef KMEANS_FINAL_PASS

void main()
{
  uint slots = uint(uFeatures + 1) * uint(uK) + 1u;
  uint i = TERROIR_GLOBAL_ID.x;
  if (i >= slots)
  {
    return;
  }
  precise double acc = totals[i];
  for (uint b = 0u; b < uBlocks; ++b)
  {
    acc = acc + partials[b * slots + i];
  }
  totals[i] = acc;
}

#else

void main()
{
  // Invocation i = b * groups + g: g < groups - 1 sums features 4g .. 4g + 3 (those < F), the
  // last one counts and sums the inertia.
  uint groups = (uint(uFeatures) + 3u) / 4u + 1u;
  uint i = TERROIR_GLOBAL_ID.x;
  uint b = i / groups;
  if (b >= uBlocks)
  {
    return;
  }
  uint g = i - b * groups;
  bool counter = g == groups - 1u;
  uint first = b * uBlockCells;
  uint last = min(first + uBlockCells, uCells);
  // Feature rows of this group, past F clamped to F - 1 (read, never written).
  uint f0 = counter ? 0u : 4u * g;
  uvec4 row = min(uvec4(f0, f0 + 1u, f0 + 2u, f0 + 3u), uvec4(uint(uFeatures) - 1u)) * uCells;

  // The invocation's accumulators, one per cluster, in `scratch` (no local array of doubles:
  // NVIDIA's compiler, driver 580.159.04, gave other values for them than the ones stored;
  // TestGPUDataPath.DoubleIdiomsOfTheKernels).
  uint base = i * uint(MAX_K);
  for (int k = 0; k < uK; ++k)
  {
    scratch[base + uint(k)] = dvec4(0.0LF);
  }
  precise double inertia = 0.0LF;
  // The accumulators of the current run of equal labels live in `run` (labels come in runs on
  // a terrain, and neighbouring invocations share the block, so the flushes are coherent); the
  // additions are those of KMeansBlockSums, in the same order.
  int current = labels[first];
  precise dvec4 run = dvec4(0.0LF);
  for (uint c = first; c < last; ++c)
  {
    int label = labels[c];
    if (label != current)
    {
      scratch[base + uint(current)] = run;
      current = label;
      run = scratch[base + uint(current)];
    }
    if (counter)
    {
      run.x = run.x + 1.0LF;
      inertia = inertia + double(distances[c]);
    }
    else
    {
      uvec4 x = row + uvec4(c);
      run = run + dvec4(features[x.x], features[x.y], features[x.z], features[x.w]);
    }
  }
  scratch[base + uint(current)] = run;
  uint slots = uint(uFeatures + 1) * uint(uK) + 1u;
  uint record = b * slots;
  if (counter)
  {
    for (int k = 0; k < uK; ++k)
    {
      partials[record + uint(uFeatures * uK + k)] = scratch[base + uint(k)].x;
    }
    partials[record + slots - 1u] = inertia;
    return;
  }
  for (uint q = 0u; q < 4u && f0 + q < uint(uFeatures); ++q)
  {
    for (int k = 0; k < uK; ++k)
    {
      partials[record + (f0 + q) * uint(uK) + uint(k)] = scratch[base + uint(k)][q];
    }
  }
}

#endif
