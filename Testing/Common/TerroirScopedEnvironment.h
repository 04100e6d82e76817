// Sets or unsets one environment variable for a scope and restores its earlier value (header
// only, so that every test folder can use it, the unit tests included).
#ifndef TerroirScopedEnvironment_h
#define TerroirScopedEnvironment_h

#include <cstdlib>
#include <string>

namespace terroir_test
{

class ScopedEnvironment
{
public:
  /// Sets `name` to `value`, or unsets it when `value` is null.
  ScopedEnvironment(const char* name, const char* value)
    : Name(name)
  {
    const char* old = std::getenv(name);
    this->HadOld = old != nullptr;
    this->Old = old ? old : "";
    this->Set(value);
  }
  ~ScopedEnvironment() { this->Set(this->HadOld ? this->Old.c_str() : nullptr); }
  ScopedEnvironment(const ScopedEnvironment&) = delete;
  ScopedEnvironment& operator=(const ScopedEnvironment&) = delete;

  void Set(const char* value)
  {
    if (value)
    {
      setenv(this->Name.c_str(), value, 1);
    }
    else
    {
      unsetenv(this->Name.c_str());
    }
  }

private:
  std::string Name;
  bool HadOld = false;
  std::string Old;
};

} // namespace terroir_test

#endif
