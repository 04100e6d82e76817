// KMeansPartialSums.comp: step 2 of a Lloyd iteration (per-cluster sums, counts, inertia) for
// the cells of one chunk; mirrors terroir::clustering::KMeansBlockSums and the block-order total
// of KMeansCPUEngine::Sums (Filters/Clustering/Core/KMeans.{h,cxx}), bit for bit.
// Double precision, like WaterFlow.comp: the core sums in double, and the centres must be the
// CPU's bits.
//
// Two entry points, chosen by a define:
//
// (default) block pass: one invocation per (block b of the chunk, slot j), j = 0..F: slot j < F
//   sums feature j, slot F counts the members (as doubles, exact) and sums the inertia. The
//   invocation walks the block's cells (KMeansBlockCells = uBlockCells, fewer in the last block
//   of the data) in cell order with one double accumulator per cluster, starting from 0:
//   acc[label(c)] += double(x_jc) (slot F: += 1, and inertia += double(d2(c)) over every cell),
//   exactly the additions of KMeansBlockSums in the same order (the accumulator of the current
//   run of equal labels is kept in a register, as the core's GroupSums does). It writes record b of
//   `partials`: R = (F + 1) * K + 1 doubles, [j * K + k] = acc[k], [(F + 1) * K] = inertia.
//   Invocation i = b * (F + 1) + j, so neighbouring invocations share a block (and its labels).
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
//   4            double totals[R]       final pass: read and written (running totals)
//                                       host layout: sums[k * F + f] = totals[f * K + k],
//                                       counts[k] = totals[F * K + k], inertia = totals[R - 1]
// Uniforms: uint uCells (n), int uFeatures (F >= 1), int uK (1..MAX_K), uint uBlocks (B),
// uint uBlockCells (KMeansBlockCells).
// Defines: LOCAL_X (work group, 64 by default); MAX_K (accumulators per invocation, >= uK,
// KMeansMaxClusters = 64 by default; the host passes K rounded up to a power of two);
// KMEANS_FINAL_PASS (the final pass). Dispatch ceil(B * (F + 1) / LOCAL_X) groups (block
// pass) or ceil(R / LOCAL_X) groups (final pass), 1-D.

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

uniform uint uCells;
uniform int uFeatures;
uniform int uK;
uniform uint uBlocks;
uniform uint uBlockCells;

#ifdef KMEANS_FINAL_PASS

void main()
{
  uint slots = uint(uFeatures + 1) * uint(uK) + 1u;
  uint i = gl_GlobalInvocationID.x;
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
  uint perBlock = uint(uFeatures + 1);
  uint i = gl_GlobalInvocationID.x;
  uint b = i / perBlock;
  if (b >= uBlocks)
  {
    return;
  }
  uint j = i - b * perBlock;
  bool counter = j == uint(uFeatures);
  uint first = b * uBlockCells;
  uint last = min(first + uBlockCells, uCells);
  // Slot F reads feature 0 (any valid address) and adds 1 instead.
  uint x = (counter ? 0u : j * uCells) + first;

  double acc[MAX_K];
  for (int k = 0; k < MAX_K; ++k)
  {
    acc[k] = 0.0LF;
  }
  precise double inertia = 0.0LF;
  // The accumulator of the current run of equal labels lives in `run` (labels come in runs on
  // a terrain, and neighbouring invocations share the block, so the flushes are coherent); the
  // additions are those of KMeansBlockSums, in the same order.
  int current = labels[first];
  precise double run = 0.0LF;
  for (uint c = first; c < last; ++c, ++x)
  {
    int label = labels[c];
    if (label != current)
    {
      acc[current] = run;
      current = label;
      run = acc[current];
    }
    run = run + (counter ? 1.0LF : double(features[x]));
    if (counter)
    {
      inertia = inertia + double(distances[c]);
    }
  }
  acc[current] = run;
  uint slots = perBlock * uint(uK) + 1u;
  uint record = b * slots + j * uint(uK);
  for (int k = 0; k < uK; ++k)
  {
    partials[record + uint(k)] = acc[k];
  }
  if (counter)
  {
    partials[b * slots + slots - 1u] = inertia;
  }
}

#endif
