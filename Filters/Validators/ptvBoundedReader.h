/**
 * @file ptvBoundedReader.h
 * @brief Reads little-endian values of a file inside a window, never past the file's end (private).
 *
 * Used by the layout checks that run before OpenVDB and OpenEXR see a file
 * (ptvOpenVDBLayout.cxx, ptvEXRLayout.cxx): both libraries trust the sizes stored in a file and
 * allocate them before reading, so every size is first checked here against what the file holds.
 * Each read fails, without moving, when it would cross @c Limit (the end of the current section,
 * by default the end of the file).
 */
#ifndef ptvBoundedReader_h
#define ptvBoundedReader_h

#include <cstdint> // for std::uint64_t
#include <fstream> // for std::ifstream
#include <string>  // for std::string

namespace ptv
{

class BoundedReader
{
public:
  BoundedReader(std::ifstream& in, std::uint64_t fileSize)
    : Limit(fileSize)
    , FileSize(fileSize)
    , In(in)
  {
  }

  /// Offset of the next byte to read.
  std::uint64_t Position = 0;
  /// End of the section being read (at most FileSize).
  std::uint64_t Limit;
  const std::uint64_t FileSize;

  /// To call after someone else moved the stream (the next read seeks).
  void Resync() { this->Streamed = ~std::uint64_t(0); }

  /// Bytes left before Limit.
  std::uint64_t Left() const { return this->Position < this->Limit ? this->Limit - this->Position : 0; }

  /// Reads @a n bytes into @a out, or skips them when @a out is null.
  bool Bytes(void* out, std::uint64_t n)
  {
    if (n > this->Limit || this->Position > this->Limit - n)
    {
      return false;
    }
    if (out && n)
    {
      if (this->Streamed != this->Position) // a seek drops the stream's buffer: only when needed
      {
        this->In.clear();
        this->In.seekg(static_cast<std::streamoff>(this->Position));
      }
      this->In.read(static_cast<char*>(out), static_cast<std::streamsize>(n));
      if (!this->In)
      {
        this->Streamed = ~std::uint64_t(0);
        return false;
      }
      this->Streamed = this->Position + n;
    }
    this->Position += n;
    return true;
  }

  /// A little-endian value (the only byte order of both formats and of the supported hosts).
  template <typename T>
  bool Value(T& v)
  {
    return this->Bytes(&v, sizeof(T));
  }

  /// A string stored as uint32 length + characters (OpenVDB); strings over @a keep characters
  /// are skipped and returned empty.
  bool SizedString(std::string& text, std::uint32_t keep = 4096)
  {
    std::uint32_t n = 0;
    if (!this->Value(n))
    {
      return false;
    }
    if (n > keep)
    {
      text.clear();
      return this->Bytes(nullptr, n);
    }
    text.assign(n, '\0');
    return this->Bytes(n ? &text[0] : nullptr, n);
  }

  /// A NUL-terminated string of at most @a maxLength characters (OpenEXR attribute names/types).
  bool TerminatedString(std::string& text, std::uint64_t maxLength)
  {
    text.clear();
    for (;;)
    {
      char c = 0;
      if (!this->Value(c))
      {
        return false;
      }
      if (c == '\0')
      {
        return true;
      }
      if (text.size() == maxLength)
      {
        return false;
      }
      text.push_back(c);
    }
  }

private:
  std::ifstream& In;
  std::uint64_t Streamed = ~std::uint64_t(0); // where the stream is, if known
};

} // namespace ptv

#endif
