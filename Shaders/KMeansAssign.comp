// KMeansAssign.comp: step 1 of a Lloyd iteration (assignment) for the cells of one chunk;
// mirrors terroir::clustering::KMeansAssignRange (Filters/Clustering/Core/KMeans.{h,cxx}).
// For every cell and k = 0..K-1, d2 = sum over f = 0..F-1, in that order, of (x_f - m_kf)^2 in
// float (`d = x - m; acc = acc + d * d`, `precise`: no fused multiply-add, as the core, which is
// built with -ffp-contract=off); the label is the k of the smallest d2, ties to the lowest k
// (strict `<`, k in increasing order); the label and that d2 are written, and each work group
// counts the cells whose label changed (integer atomics on one shared counter, no float
// atomics) into its slot of `changed`.
//
// Register blocking: one invocation does 8 consecutive cells (two vec4s) against
// CENTRES_PER_PASS centres at a time, so one load of a centre value serves 8 cells and one load
// of a feature serves CENTRES_PER_PASS centres (on llvmpipe a buffer load at a varying index is
// done lane by lane, and these loads, not the arithmetic, set the speed). Each component of each
// accumulator does the scalar loop's float operations in the same order.
//
// The feature matrix is split into chunks of whole KMeansBlockCells blocks so that one chunk
// fits GL_MAX_SHADER_STORAGE_BLOCK_SIZE; each chunk has its own buffers, indexed from the
// chunk's first cell (local cell c = global cell - chunk start).
//
// Bindings (std430; n = uCells cells of the chunk, F = uFeatures, K = uK):
//   0  readonly  float features[F*n]   feature-major: feature f of cell c at f * n + c
//                                      (the prepared features, KMeansFeatures' layout)
//   1  readonly  float centres[64*F]   row k = centre k (KMeansMaxClusters rows; rows >= K are
//                                      read when K is not a multiple of CENTRES_PER_PASS, and
//                                      their results ignored)
//   2            int   labels[n]       in: previous labels (-1 before the first assignment);
//                                      out: new labels 0..K-1
//   3  writeonly float distances[n]    out: the smallest d2 (squared distance to the own centre)
//   4  writeonly uint  changed[]       out: changed labels of work group g of this chunk at
//                                      changed[uGroupOffset + g]
// Uniforms: uint uCells (n), int uFeatures (F >= 1), int uK (1..64), uint uGroupOffset.
// Defines: LOCAL_X (work group, 32 by default: 8 * LOCAL_X cells per group); CENTRES_PER_PASS
// (4 by default; the host passes 4 for K <= 8, else 8). Dispatch ceil(n / (8 * LOCAL_X)) groups
// (1-D; the host keeps chunks small enough for GL_MAX_COMPUTE_WORK_GROUP_COUNT[0]).

#ifndef LOCAL_X
#define LOCAL_X 32
#endif
#ifndef CENTRES_PER_PASS
#define CENTRES_PER_PASS 4
#endif

layout(local_size_x = LOCAL_X, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer FeatureBuffer { float features[]; };
layout(std430, binding = 1) readonly buffer CentreBuffer { float centres[]; };
layout(std430, binding = 2) buffer LabelBuffer { int labels[]; };
layout(std430, binding = 3) writeonly buffer DistanceBuffer { float distances[]; };
layout(std430, binding = 4) writeonly buffer ChangedBuffer { uint changed[]; };

uniform uint uCells;
uniform int uFeatures;
uniform int uK;
uniform uint uGroupOffset;

shared uint sChanged;

void main()
{
  uint lid = gl_LocalInvocationID.x;
  uint c0 = 8u * TERROIR_GLOBAL_ID.x;
  if (lid == 0u)
  {
    sChanged = 0u;
  }
  memoryBarrierShared();
  barrier();
  if (c0 < uCells)
  {
    // Cells past the end (in the chunk's last invocation) read the last cell; not written.
    uint last = uCells - 1u;
    uvec4 cellA = min(uvec4(c0, c0 + 1u, c0 + 2u, c0 + 3u), uvec4(last));
    uvec4 cellB = min(uvec4(c0 + 4u, c0 + 5u, c0 + 6u, c0 + 7u), uvec4(last));
    uint stride = uint(uFeatures);
    ivec4 bestA = ivec4(0);
    ivec4 bestB = ivec4(0);
    vec4 bestD2A = vec4(0.0);
    vec4 bestD2B = vec4(0.0);
    for (int k0 = 0; k0 < uK; k0 += CENTRES_PER_PASS)
    {
      precise vec4 accA[CENTRES_PER_PASS];
      precise vec4 accB[CENTRES_PER_PASS];
      for (int i = 0; i < CENTRES_PER_PASS; ++i)
      {
        accA[i] = vec4(0.0);
        accB[i] = vec4(0.0);
      }
      uint m = uint(k0) * stride;
      uvec4 xa = cellA;
      uvec4 xb = cellB;
      for (int f = 0; f < uFeatures; ++f)
      {
        vec4 va = vec4(features[xa.x], features[xa.y], features[xa.z], features[xa.w]);
        vec4 vb = vec4(features[xb.x], features[xb.y], features[xb.z], features[xb.w]);
        uint mf = m + uint(f);
        for (int i = 0; i < CENTRES_PER_PASS; ++i)
        {
          vec4 ci = vec4(centres[mf + uint(i) * stride]);
          precise vec4 da = va - ci;
          precise vec4 db = vb - ci;
          accA[i] = accA[i] + da * da;
          accB[i] = accB[i] + db * db;
        }
        xa += uvec4(uCells);
        xb += uvec4(uCells);
      }
      for (int i = 0; i < CENTRES_PER_PASS && k0 + i < uK; ++i)
      {
        bvec4 closerA = k0 + i == 0 ? bvec4(true) : lessThan(accA[i], bestD2A);
        bvec4 closerB = k0 + i == 0 ? bvec4(true) : lessThan(accB[i], bestD2B);
        bestD2A = mix(bestD2A, accA[i], closerA);
        bestD2B = mix(bestD2B, accB[i], closerB);
        for (int j = 0; j < 4; ++j)
        {
          bestA[j] = closerA[j] ? k0 + i : bestA[j];
          bestB[j] = closerB[j] ? k0 + i : bestB[j];
        }
      }
    }
    uint moved = 0u;
    for (int j = 0; j < 8; ++j)
    {
      uint c = c0 + uint(j);
      int b = j < 4 ? bestA[j & 3] : bestB[j & 3];
      float d2 = j < 4 ? bestD2A[j & 3] : bestD2B[j & 3];
      if (c < uCells)
      {
        if (labels[c] != b)
        {
          labels[c] = b;
          ++moved;
        }
        distances[c] = d2;
      }
    }
    if (moved > 0u)
    {
      atomicAdd(sChanged, moved);
    }
  }
  memoryBarrierShared();
  barrier();
  if (lid == 0u)
  {
    changed[uGroupOffset + TERROIR_WORKGROUP_ID.x] = sChanged;
  }
}
