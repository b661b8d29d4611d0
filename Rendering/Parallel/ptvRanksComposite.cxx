// Ranks::CompositeFrame: a split volume's pieces composited by direct send. Every process
// composites its own share of the pixels (process k: pixels [n k / N, n (k + 1) / N) of n):
// each process sends every other one that share of its piece's traced passes (one ScatterV per
// piece), composites its share of all the pieces in view order (ptvPieces.h), and process 0
// gathers the composited shares (one GatherV). A process sends and receives (N - 1) / N of one
// image's passes, process 0 that again in the final gather: the traffic per process does not
// grow with the number of processes, where gathering every piece on process 0 made it
// receive N - 1 images. The image is the same: each pixel is composited from the same samples
// in the same order by the same function.
#include "ptvRanks.h"

#include "vtkCommunicator.h"
#include "vtkMultiProcessController.h"

#include <algorithm>

namespace ptv
{
namespace
{
/// The first pixel of process @a k's share of @a pixels among @a size processes.
std::size_t ShareBegin(std::size_t pixels, int k, int size)
{
  return pixels * static_cast<std::size_t>(k) / static_cast<std::size_t>(size);
}
}

//------------------------------------------------------------------------------
bool Ranks::CompositeFrame(PassBuffers& frame, int passes, const PieceView& piece, int threads)
{
  const std::size_t pixels =
    static_cast<std::size_t>(frame.GetWidth()) * static_cast<std::size_t>(frame.GetHeight());
  const int size = this->Size;
  const bool root = this->Rank == 0;
  // Every piece's box and far distance, on every process (each composites a share).
  constexpr int kMeta = 7;
  double meta[kMeta];
  std::copy(piece.Box.begin(), piece.Box.end(), meta);
  meta[6] = piece.Far;
  std::vector<double> metas(static_cast<std::size_t>(kMeta) * size);
  this->Controller->AllGather(meta, metas.data(), kMeta);
  std::vector<PieceBox> boxes(static_cast<std::size_t>(size));
  std::vector<float> fars(static_cast<std::size_t>(size));
  for (int r = 0; r < size; ++r)
  {
    std::copy(metas.begin() + kMeta * r, metas.begin() + kMeta * r + 6, boxes[r].begin());
    fars[r] = static_cast<float>(metas[kMeta * r + 6]);
  }
  const std::vector<int> order = ViewOrder(boxes, piece.Eye, piece.Dir, piece.Parallel);
  this->LastBytesReceived = 0;
  if (order.empty())
  {
    return root; // no piece holds anything: process 0's own frame (the same misses)
  }

  // The passes sent: the traced ones the frame keeps (the same on every process).
  std::vector<int> sent;
  std::size_t floats = 0; // per pixel
  for (int p = 0; p < passes && p < kTracedPassCount; ++p)
  {
    if (frame.Data(p))
    {
      sent.push_back(p);
      floats += static_cast<std::size_t>(GetPassInfo(p).Components);
    }
  }
  // This piece's passes by destination: process k's share of every pass, one after the other.
  std::vector<vtkIdType> lengths(static_cast<std::size_t>(size));
  std::vector<vtkIdType> offsets(static_cast<std::size_t>(size));
  this->Outgoing.resize(pixels * floats);
  std::size_t at = 0;
  for (int k = 0; k < size; ++k)
  {
    offsets[k] = static_cast<vtkIdType>(at);
    const std::size_t begin = ShareBegin(pixels, k, size), end = ShareBegin(pixels, k + 1, size);
    for (const int p : sent)
    {
      const std::size_t c = static_cast<std::size_t>(GetPassInfo(p).Components);
      std::copy(frame.Data(p) + c * begin, frame.Data(p) + c * end, this->Outgoing.data() + at);
      at += c * (end - begin);
    }
    lengths[k] = static_cast<vtkIdType>(at) - offsets[k];
  }

  // Direct send: process r scatters its piece's shares; this process receives its share of
  // every piece.
  const std::size_t begin = ShareBegin(pixels, this->Rank, size);
  const std::size_t mine = ShareBegin(pixels, this->Rank + 1, size) - begin;
  const std::size_t chunk = mine * floats; // one piece's share
  this->Incoming.resize(chunk * size);
  for (int r = 0; r < size; ++r)
  {
    this->Controller->ScatterV(this->Outgoing.data(), this->Incoming.data() + chunk * r,
      lengths.data(), offsets.data(), static_cast<vtkIdType>(chunk), r);
  }
  this->LastBytesReceived += sizeof(float) * chunk * static_cast<std::size_t>(size - 1);

  // The share of every piece, per pass (piece after piece), composited in view order.
  std::vector<const float*> gathered(kTracedPassCount, nullptr);
  std::size_t passOffset = 0; // of the pass within a piece's share
  for (const int p : sent)
  {
    const std::size_t c = static_cast<std::size_t>(GetPassInfo(p).Components);
    this->Gathered[p].resize(c * mine * size);
    for (int r = 0; r < size; ++r)
    {
      const float* from = this->Incoming.data() + chunk * r + passOffset;
      std::copy(from, from + c * mine, this->Gathered[p].data() + c * mine * r);
    }
    gathered[p] = this->Gathered[p].data();
    passOffset += c * mine;
  }
  this->Composited.SetScatterPasses(frame.GetScatterPasses());
  this->Composited.Resize(static_cast<int>(mine), 1);
  CompositePieces(gathered, mine, order, fars, piece.Far, threads, this->Composited);

  // Process 0 gathers the composited shares into its frame.
  this->Outgoing.resize(chunk);
  at = 0;
  for (const int p : sent)
  {
    const std::size_t c = static_cast<std::size_t>(GetPassInfo(p).Components);
    const float* from = this->Composited.Data(p);
    std::copy(from, from + c * mine, this->Outgoing.data() + at);
    at += c * mine;
  }
  for (int k = 0; k < size; ++k)
  {
    lengths[k] = static_cast<vtkIdType>(
      floats * (ShareBegin(pixels, k + 1, size) - ShareBegin(pixels, k, size)));
    offsets[k] = k == 0 ? 0 : offsets[k - 1] + lengths[k - 1];
  }
  this->Incoming.resize(root ? pixels * floats : 0);
  this->Controller->GatherV(this->Outgoing.data(), this->Incoming.data(),
    static_cast<vtkIdType>(chunk), lengths.data(), offsets.data(), 0);
  if (!root)
  {
    return false;
  }
  this->LastBytesReceived += sizeof(float) * (pixels * floats - chunk);
  for (int k = 0; k < size; ++k)
  {
    const std::size_t first = ShareBegin(pixels, k, size);
    const std::size_t count = ShareBegin(pixels, k + 1, size) - first;
    const float* from = this->Incoming.data() + offsets[k];
    for (const int p : sent)
    {
      const std::size_t c = static_cast<std::size_t>(GetPassInfo(p).Components);
      std::copy(from, from + c * count, frame.Data(p) + c * first);
      from += c * count;
    }
  }
  return true;
}
}
