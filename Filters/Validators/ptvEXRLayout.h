/**
 * @file ptvEXRLayout.h
 * @brief Checks an OpenEXR file's headers and offset tables before OpenEXR reads it (private).
 *
 * OpenEXR 3.1's C++ reader allocates every header attribute with the size stored in front of it
 * (a corrupt size made it allocate up to 2 GB, found by fuzz_exr_pass_reader) and its offset
 * table with the chunk count implied by the data window. CheckEXRLayout walks what
 * Imf::Header::readFrom reads: the magic number and version flags, each header's attributes
 * (name and type lengths; a size that is not negative and fits the file; fixed-size types
 * declaring exactly their size; the contents of chlist, preview, stringvector and floatvector
 * values, which OpenEXR parses by content), the end of each header, and then that every part's
 * offset table (8 bytes per chunk: scan-line blocks of the data window, level-0 tiles, or the
 * multi-part "chunkCount") fits in the file. Pixel data itself is OpenEXR's to decode.
 */
#ifndef ptvEXRLayout_h
#define ptvEXRLayout_h

#include "vtkPTVFiltersModule.h" // for export macro

#include <string> // for std::string

namespace ptv
{

/// What the walk learnt of the first part: its data window's size and number of channels.
struct EXRLayoutSummary
{
  long long Width = 0;
  long long Height = 0;
  int Channels = 0;
};

/// True if @a file passes the check (and @a summary, when given, describes its first part);
/// otherwise false with @a error saying what is wrong (the caller names the file).
VTKPTVFILTERS_EXPORT bool CheckEXRLayout(
  const std::string& file, std::string& error, EXRLayoutSummary* summary = nullptr);

} // namespace ptv

#endif
