// Shared by the fuzz harnesses: an invariant that does not hold aborts the run, so that
// libFuzzer saves the input (a plain assert would vanish under NDEBUG).
#ifndef FuzzCheck_h
#define FuzzCheck_h

namespace terroir_fuzz
{
inline void Check(bool condition)
{
  if (!condition)
  {
    __builtin_trap();
  }
}
} // namespace terroir_fuzz

#endif
