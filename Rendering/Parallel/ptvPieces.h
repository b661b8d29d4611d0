/**
 * @file ptvPieces.h
 * @brief Private: the pieces of a distributed volume (vtkPathTracedVolumeMapper::
 *        DistributedVolume), put back into one frame: their order along the view, and the
 *        per-pixel "over" of their traced passes (Kernels/ptvTraceParams.h, OverSample).
 *
 * Every process traces camera rays through its own piece only (TraceParams::CameraBox), with
 * its own random numbers, so along each ray the pieces' samples are independent samples of the
 * ray's segments. Compositing them front to back gives a sample of the whole ray. The order
 * comes from the pieces' boxes: a block decomposition (ParaView's, and any recursive bisection)
 * is split by an axis-aligned plane that no box crosses; the half on the eye's side (for a
 * parallel projection: the half the rays start in) comes first, and each half is ordered the
 * same way. Boxes that no such plane separates (not a block decomposition) fall back to the
 * distance from the eye to their centres.
 */
#ifndef ptvPieces_h
#define ptvPieces_h

#include <array>
#include <cstddef>
#include <vector>

namespace ptv
{
class PassBuffers;

/// A piece's own box in the volume's structured point indices: x0, x1, y0, y1, z0, z1.
using PieceBox = std::array<double, 6>;

/// What a process tells process 0 about its piece each frame (and what process 0 orders by).
struct PieceView
{
  PieceBox Box = { { 0, -1, 0, -1, 0, -1 } }; ///< own box, structured coordinates
  double Eye[3] = { 0, 0, 0 };                 ///< the camera position, same coordinates
  double Dir[3] = { 0, 0, 1 };                 ///< the view direction, same coordinates
  bool Parallel = false;                       ///< parallel projection
  float Far = 1.f;                             ///< depth of misses (Camera.FarDistance)
};

/**
 * The pieces, front first, as seen from @a eye (perspective) or along @a dir (@a parallel);
 * both in the same structured coordinates as @a boxes. Empty boxes (x0 > x1) go last.
 */
std::vector<int> ViewOrder(
  const std::vector<PieceBox>& boxes, const double eye[3], const double dir[3], bool parallel);

/**
 * Composite the pieces' traced frames into @a out (already sized): @a gathered[p] holds pass p
 * of every piece, piece after piece (what vtkMultiProcessController::Gather leaves), for
 * @a pixels pixels; @a order is ViewOrder's; @a fars[k] is piece k's depth of misses, and the
 * result's misses lie at @a far.
 */
void CompositePieces(const std::vector<const float*>& gathered, std::size_t pixels,
  const std::vector<int>& order, const std::vector<float>& fars, float far, int threads,
  PassBuffers& out);
}

#endif
