// Channel naming of render-pass EXR files, shared by vtkPTVEXRPassWriter and
// vtkPTVEXRPassReader. No OpenEXR or VTK types: plain strings only.
//
// Convention (the same as Training/ptv_training/exr_io.py, where they overlap):
//   Radiance        R, G, B              Alpha            A   (reader also takes alpha.A)
//   Albedo          albedo.R/G/B         Depth            Z
//   Position        P.X/Y/Z              Normal           N.X/Y/Z
//   ScatterDepth    scatter.Z            ScatterPosition  scatter.P.X/Y/Z
//   ScatterNormal   scatter.N.X/Y/Z      Denoised         denoised.R/G/B
//   Coverage        coverage.A
//   Footprint       footprint.A
//   any other array <name>.<suffix>: 1 component Y, 3 components R,G,B, 4 components R,G,B,A,
//                   any other count 0,1,2,... (e.g. BlendWeights.0, BlendWeights.1).
// The writer also stores the layout in the string attribute "ptv.passes"
// ("Radiance=R,G,B;Alpha=A;..."), so that the reader restores names and component order
// exactly; files without it (from other tools) are grouped by the convention above.
#ifndef ptvEXRChannels_h
#define ptvEXRChannels_h

#include <string>
#include <vector>

namespace ptv
{

/// Name of the header attribute holding the pass layout.
constexpr const char* kPassLayoutAttribute = "ptv.passes";

/// One pass (a VTK point-data array) and its EXR channels, in component order.
struct EXRPassLayout
{
  std::string Name;
  std::vector<std::string> Channels;
};

/// The channels of array @a name with @a components components (convention above).
std::vector<std::string> EXRChannelsForPass(const std::string& name, int components);

/// "Radiance=R,G,B;Alpha=A" for a list of passes.
std::string FormatEXRPassLayout(const std::vector<EXRPassLayout>& passes);

/**
 * Parse FormatEXRPassLayout()'s text. Returns false (and @a passes empty) when the text is not
 * in that form, names an empty pass, or a channel that is not in @a available.
 */
bool ParseEXRPassLayout(const std::string& text, const std::vector<std::string>& available,
  std::vector<EXRPassLayout>& passes);

/**
 * Group the channel names of a file without a layout attribute into passes: the known passes
 * first (their channels in component order), then the rest by the text before the last '.',
 * components ordered R,G,B,A / X,Y,Z / numeric / alphabetical. Every channel ends up in exactly
 * one pass.
 */
std::vector<EXRPassLayout> GroupEXRChannels(const std::vector<std::string>& channels);

} // namespace ptv

#endif
