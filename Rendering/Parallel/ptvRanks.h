/**
 * @file ptvRanks.h
 * @brief Private: the processes (MPI ranks) that trace one frame together
 *        (vtkPathTracedVolumeMapper::SetController), each with the whole volume or, distributed,
 *        each with its own piece.
 *
 * With the whole volume everywhere, process r of N traces sample block f * N + r of frame f:
 * the N blocks of a frame are the blocks one process would trace with N times the samples per
 * frame; GatherFrame sums the frame's traced passes on process 0 and divides by N, which gives
 * it that process's frame (the same estimator, the same image up to float rounding).
 * Distributed, every process traces the frame's camera rays through its own piece only, with
 * its own random numbers after the ray (PieceStream), and GatherFrame composites the pieces'
 * frames in view order (ptvPieces.h), each process a share of the pixels, into process 0's
 * frame: one frame of the whole volume. Process 0
 * alone accumulates, denoises and shows; the others only trace. Decisions (restart, trace, when
 * a still render stops) are process 0's, broadcast (Agree), so that every process makes the
 * same collective calls in the same order. Without a controller, or with one process, every
 * call is a no-op.
 */
#ifndef ptvRanks_h
#define ptvRanks_h

#include "ptvPassBuffers.h"
#include "ptvPieces.h"

#include "vtkSmartPointer.h"

#include <cstdint>
#include <vector>

class vtkMultiProcessController;

namespace ptv
{
class PassBuffers;

class Ranks
{
public:
  Ranks();
  ~Ranks();

  /// The processes to work with (nullptr: this process alone).
  void SetController(vtkMultiProcessController* controller);
  vtkMultiProcessController* GetController() const;

  int GetRank() const { return this->Rank; }
  int GetSize() const { return this->Size; }
  bool IsParallel() const { return this->Size > 1; }
  /// Whether this process shows the image (process 0; the others draw nothing).
  bool Shows() const { return this->Rank == 0; }

  /// Every process holds its own piece (true) or the whole volume (false, the default).
  void SetDistributed(bool distributed) { this->Distributed = distributed; }
  bool IsDistributed() const { return this->Distributed; }

  /**
   * Whether every process is @a ok, and (distributed) the whole volume's scalar @a ranges
   * (scalars, then colour channel: min, max each), world @a bounds and @a extent from every
   * piece's, in place (collective; alone: @a ok, values unchanged).
   */
  bool Share(bool ok, double ranges[4], double bounds[6], double extent[6]);

  /// Whether every process is @a ok (collective; alone: @a ok).
  bool AllTrue(bool ok);

  /**
   * Threads for @a requested (<= 0: every core, shared by the processes on this host, learnt
   * once by comparing host names; collective on the first call with a controller).
   */
  int Threads(int requested);

  /// The first sample of this process's block of frame @a frame with @a samples per block
  /// (distributed: the frame's samples, the same on every process).
  unsigned int FirstSample(unsigned int frame, int samples) const;

  /// TraceParams::PieceStream of this process: distributed, rank + 1 (its own random numbers
  /// after the shared camera ray); otherwise 0.
  unsigned int PieceStream() const
  {
    return this->Distributed && this->IsParallel() ? static_cast<unsigned int>(this->Rank) + 1u
                                                   : 0u;
  }

  /**
   * Process 0's @a frame becomes the whole frame (collective): the mean of the first @a passes
   * passes over the processes, or, distributed, the pieces' traced passes composited in view
   * order (@a piece: where this process's piece lies). Returns whether this process keeps the
   * frame (process 0, or the only one); the others' frames have been used.
   */
  bool GatherFrame(PassBuffers& frame, int passes, const PieceView& piece, int threads);

  /// Bytes this process received from the others in the last distributed GatherFrame.
  std::size_t GetLastBytesReceived() const { return this->LastBytesReceived; }

  /// Process 0's @a value on every process (collective).
  int Agree(int value);
  /// Process 0's @a values on every process, in place (collective).
  void Agree(std::vector<std::uint32_t>& values);

private:
  /// GatherFrame for distributed pieces: composited by direct send (ptvRanksComposite.cxx).
  bool CompositeFrame(PassBuffers& frame, int passes, const PieceView& piece, int threads);

  vtkSmartPointer<vtkMultiProcessController> Controller;
  int Rank = 0;
  int Size = 1;
  int LocalRanks = 0; ///< processes on this host; 0: not learnt yet
  bool Distributed = false;
  std::vector<float> Sum;
  /// Distributed: every piece's share of each pass, this process's share composited, and the
  /// buffers sent and received.
  std::vector<float> Gathered[kTracedPassCount];
  PassBuffers Composited{ PassSet::Traced };
  std::vector<float> Outgoing, Incoming;
  std::size_t LastBytesReceived = 0;
};
}

#endif
