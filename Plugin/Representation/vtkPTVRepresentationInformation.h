/**
 * @class vtkPTVRepresentationInformation
 * @brief The progress of a "Path Traced Volume" representation, gathered where it renders.
 *
 * ParaView pulls information-only properties from the client's copy of a proxy that also lives
 * on the client, and in client/server mode the client's copy of vtkPTVVolumeRepresentation never
 * renders: its AccumulatedFrames, ActiveBackend, ... read 0 / "none". This vtkPVInformation is
 * gathered from the process that renders instead, in any session:
 *
 * @code{.py}
 * from pathtracedvolume.vtkPTVParaViewViews import vtkPTVRepresentationInformation
 * from paraview import servermanager
 * info = vtkPTVRepresentationInformation()
 * servermanager.ActiveConnection.Session.GatherInformation(
 *     servermanager.vtkPVSession.RENDER_SERVER_ROOT, info, display.SMProxy.GetGlobalID())
 * info.GetFound(), info.GetAccumulatedFrames(), info.GetActiveBackend()
 * @endcode
 *
 * CopyFromObject() takes a vtkPTVVolumeRepresentation, or a vtkCompositeRepresentation (the
 * representation proxy ParaView shows, e.g. display.SMProxy) whose active representation is
 * one; anything else leaves Found false. Gathered from the root only (RootOnly): the first rank
 * holds the composited image that the mapper's progress describes.
 */
#ifndef vtkPTVRepresentationInformation_h
#define vtkPTVRepresentationInformation_h

#include "vtkPTVParaViewViewsModule.h" // for export macro
#include "vtkPVInformation.h"

#include <string> // for std::string

class VTKPTVPARAVIEWVIEWS_EXPORT vtkPTVRepresentationInformation : public vtkPVInformation
{
public:
  static vtkPTVRepresentationInformation* New();
  vtkTypeMacro(vtkPTVRepresentationInformation, vtkPVInformation);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Collect the progress of a vtkPTVVolumeRepresentation (directly or as active representation).
  void CopyFromObject(vtkObject* object) override;

  /// Keep the first found representation's values (root-only gathering: one process).
  void AddInformation(vtkPVInformation* other) override;

  ///@{
  /// Serialization between processes.
  void CopyToStream(vtkClientServerStream* stream) override;
  void CopyFromStream(const vtkClientServerStream* stream) override;
  ///@}

  /// Whether a Path Traced Volume representation was found (false: every value is its default).
  vtkGetMacro(Found, bool);
  /// Frames averaged so far in the current accumulation (vtkPathTracedVolumeMapper).
  vtkGetMacro(AccumulatedFrames, int);
  /// The mapper's MaximumAccumulatedFrames.
  vtkGetMacro(MaximumAccumulatedFrames, int);
  /// Whether the last render traced a new frame.
  vtkGetMacro(LastRenderTraced, bool);
  /// vtkPTVVolumeRepresentation::GetNeedsRefinement(): another render would trace a frame.
  vtkGetMacro(NeedsRefinement, bool);
  /// Milliseconds spent tracing / denoising in the last render (0 if it did not).
  vtkGetMacro(LastTraceTime, double);
  vtkGetMacro(LastDenoiseTime, double);
  /// Estimated PSNR (dB) of the shown image, and whether the last still render reached
  /// StillQuality (vtkPathTracedVolumeMapper).
  vtkGetMacro(EstimatedQuality, double);
  vtkGetMacro(StillConverged, bool);
  /// "CPU" or "CUDA" ("none" before the first frame or when not found).
  const char* GetActiveBackend() { return this->ActiveBackend.c_str(); }
  /// What the last denoise used ("" when not found).
  const char* GetDenoiserStatus() { return this->DenoiserStatus.c_str(); }

protected:
  vtkPTVRepresentationInformation();
  ~vtkPTVRepresentationInformation() override;

  bool Found = false;
  int AccumulatedFrames = 0;
  int MaximumAccumulatedFrames = 0;
  bool LastRenderTraced = false;
  bool NeedsRefinement = false;
  double LastTraceTime = 0.0;
  double LastDenoiseTime = 0.0;
  double EstimatedQuality = 0.0;
  bool StillConverged = false;
  std::string ActiveBackend = "none";
  std::string DenoiserStatus;

private:
  vtkPTVRepresentationInformation(const vtkPTVRepresentationInformation&) = delete;
  void operator=(const vtkPTVRepresentationInformation&) = delete;
};

#endif
