/**
 * @file ptvQuote.h
 * @brief Private: how the filters' error messages show a path or name: 'text'.
 */
#ifndef ptvQuote_h
#define ptvQuote_h

#include <string>

namespace ptv
{
/// @a text in single quotes, for error messages ("cannot open 'x.vdb': ...").
inline std::string Quote(const std::string& text)
{
  return "'" + text + "'";
}
}

#endif
