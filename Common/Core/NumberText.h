/**
 * @file NumberText.h
 * @brief A number as people write it in messages and tables: `significantDigits` significant
 * digits, no trailing zeros ("2.5", "1e-06", "nan"), the C++ stream's default notation. The one
 * helper every filter, command and script parser uses for that (plain C++, header only).
 */
#ifndef terroir_NumberText_h
#define terroir_NumberText_h

#include <sstream>
#include <string>

namespace terroir
{

inline std::string NumberText(double v, int significantDigits = 10)
{
  std::ostringstream os;
  os.precision(significantDigits);
  os << v;
  return os.str();
}

} // namespace terroir

#endif
