/**
 * @file ptvRanks.h
 * @brief Private: the processes (MPI ranks) that trace one frame together, each with the whole
 *        volume (vtkPathTracedVolumeMapper::SetController).
 *
 * With N processes, process r traces sample block f * N + r of frame f, so the N blocks of a
 * frame are the blocks one process would trace with N times the samples per frame;
 * GatherFrame sums the frame's traced passes on process 0 and divides by N, which gives it that
 * process's frame (the same estimator, the same image up to float rounding). Process 0 alone
 * accumulates, denoises and shows; the others only trace. Decisions (restart, trace, when a still
 * render stops) are process 0's, broadcast (Agree), so that every process makes the same
 * collective calls in the same order. Without a controller, or with one process, every call is a
 * no-op.
 */
#ifndef ptvRanks_h
#define ptvRanks_h

#include "vtkSmartPointer.h"

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

  /**
   * Threads for @a requested (<= 0: every core, shared by the processes on this host, learnt
   * once by comparing host names; collective on the first call with a controller).
   */
  int Threads(int requested);

  /// The first sample of this process's block of frame @a frame with @a samples per block.
  unsigned int FirstSample(unsigned int frame, int samples) const;

  /**
   * The mean of the first @a passes passes of @a frame over the processes, into process 0's
   * @a frame (collective). Returns whether this process keeps the frame (process 0, or the only
   * one); the others' frames have been used.
   */
  bool GatherFrame(PassBuffers& frame, int passes);

  /// Process 0's @a value on every process (collective).
  int Agree(int value);

private:
  vtkSmartPointer<vtkMultiProcessController> Controller;
  int Rank = 0;
  int Size = 1;
  int LocalRanks = 0; ///< processes on this host; 0: not learnt yet
  std::vector<float> Sum;
};
}

#endif
