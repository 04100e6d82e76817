// KMeansAssign.comp: step 1 of a Lloyd iteration (assignment) for the cells of one chunk;
// mirrors terroir::clustering::KMeansAssignRange (Filters/Clustering/Core/KMeans.{h,cxx}).
// One invocation per cell: for k = 0..K-1, d2 = sum over f = 0..F-1, in that order, of
// (x_f - m_kf)^2 in float (`d = x - m; acc = acc + d * d`, `precise`: no fused multiply-add,
// as the core, which is built with -ffp-contract=off); the label is the k of the smallest d2,
// ties to the lowest k (strict `<`); the label and that d2 are written, and each work group
// counts the cells whose label changed (a shared-memory integer count, no float atomics) into
// its slot of `changed`.
//
// The feature matrix is split into chunks of whole KMeansBlockCells blocks so that one chunk
// fits GL_MAX_SHADER_STORAGE_BLOCK_SIZE; each chunk has its own buffers, indexed from the
// chunk's first cell (local cell c = global cell - chunk start).
//
// Bindings (std430; n = uCells cells of the chunk, F = uFeatures, K = uK):
//   0  readonly  float features[F*n]   feature-major: feature f of cell c at f * n + c
//                                      (prepared features, KMeansFeatures' layout per chunk)
//   1  readonly  float centres[K*F]    row k = centre k
//   2            int   labels[n]       in: previous labels (-1 before the first assignment);
//                                      out: new labels 0..K-1
//   3  writeonly float distances[n]    out: the smallest d2 (squared distance to the own centre)
//   4  writeonly uint  changed[]       out: changed labels of work group g of this chunk at
//                                      changed[uGroupOffset + g]
// Uniforms: uint uCells (n), int uFeatures (F >= 1), int uK (1..64), uint uGroupOffset.
// Work group LOCAL_X (define, 256 by default); dispatch ceil(n / LOCAL_X) groups (1-D; the
// host keeps chunks small enough for GL_MAX_COMPUTE_WORK_GROUP_COUNT[0]).

#ifndef LOCAL_X
#define LOCAL_X 256
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
  uint c = gl_WorkGroupID.x * uint(LOCAL_X) + lid;
  if (lid == 0u)
  {
    sChanged = 0u;
  }
  memoryBarrierShared();
  barrier();
  if (c < uCells)
  {
    int best = 0;
    float bestD2 = 0.0;
    for (int k = 0; k < uK; ++k)
    {
      uint m = uint(k * uFeatures);
      uint x = c;
      precise float acc = 0.0;
      for (int f = 0; f < uFeatures; ++f)
      {
        precise float d = features[x] - centres[m + uint(f)];
        acc = acc + d * d;
        x += uCells;
      }
      if (k == 0 || acc < bestD2)
      {
        best = k;
        bestD2 = acc;
      }
    }
    if (labels[c] != best)
    {
      atomicAdd(sChanged, 1u);
      labels[c] = best;
    }
    distances[c] = bestD2;
  }
  memoryBarrierShared();
  barrier();
  if (lid == 0u)
  {
    changed[uGroupOffset + gl_WorkGroupID.x] = sChanged;
  }
}
