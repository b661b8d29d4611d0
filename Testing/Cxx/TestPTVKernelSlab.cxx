// Analytic checks of the path-tracing kernel (Rendering/Kernels) against closed forms.
//
// Scene: a homogeneous slab, z in [0, L] world, x and y in [-20, 20] (40x wider than thick),
// stored as a 4^3 grid of equal voxels with an anisotropic WorldToIndex. The table is constant:
// colour c, opacity alpha per UnitDistance U, so the extinction is sigma = -ln(1 - alpha) / U.
// An orthographic camera looks along +z through the slab (rays start at z = -1).
//
// 1. Directional light along +z (from behind the camera), Shade = 0, Diffuse = 1, no ambient,
//    no environment. An event at depth z has shadow path length z, so
//      E[Alpha]    = 1 - exp(-sigma L)
//      E[Radiance] = c I int_0^L sigma e^{-sigma z} e^{-sigma z} dz = c I (1 - e^{-2 sigma L}) / 2.
// 2. Environment only (light radiance 0, Environment E, AmbientOcclusion = 1, Shade = 0: one
//    uniformly distributed direction per event). With mu = cos(angle to +z), the visibility from
//    depth z of an infinite slab is V(z) = 1/2 int_0^1 [e^{-sigma (L-z)/mu} + e^{-sigma z/mu}] dmu,
//    and integrating over the event density sigma e^{-sigma z} in closed form in z leaves
//      E[Radiance] = c E J,  J = 1/2 int_0^1 [ mu/(1+mu) (1 - e^{-sigma L (1+mu)/mu})
//                                 + mu e^{-sigma L} (1 - e^{-sigma L (1-mu)/mu}) / (1-mu) ] dmu,
//    evaluated with a 200000-point midpoint rule. Directions leaving through the sides (the
//    pixels see |x|,|y| <= 1, so a side is >= 19 away) change J by < e^{-19 sigma}.
//
// Tolerance: 3 standard errors of the Monte Carlo mean (sample variance over 64x64 pixels x 16
// frames). Discretisation bias: sigma * StepWorld = 0.02 (shadow step 0.04). With L / StepWorld
// an integer the sample count is fixed, so E[Alpha] is exact; for the radiance the test also
// computes the exact expectation of the *discrete* estimator (jittered event positions
// (k + xi) dt with weights T_k a, shadow sample counts floor/ceil of d / ds averaged over the
// shadow jitter) and requires |discrete - closed form| < SE / 4, so the 3 SE test is meaningful.
//
// 3. The slab split into two pieces of a distributed volume and composited (SlabDirectLight).
// 4. The slab of 1. with ExpectedCoverage (SlabExpectedCoverage).
//
// The slabs are traced with the opacity tables corrected per step (as the mapper does); with the
// constant table the per-sample correction must give the same samples bit for bit.
//
// Also: opacity correction composition, step-table lookups, sampling moments (3 SE), the Duff
// et al. basis, and trilinear sampling / gradient / NormalToWorld on a linear field.
#include "Kernels/ptvIntegrator.h"
#include "ptvTestKernelCamera.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace
{
struct Stats
{
  long N = 0;
  double Mean = 0.0;
  double M2 = 0.0;
  void Add(double v)
  {
    ++this->N;
    const double d = v - this->Mean;
    this->Mean += d / static_cast<double>(this->N);
    this->M2 += d * (v - this->Mean);
  }
  double StdErr() const
  {
    return std::sqrt(this->M2 / static_cast<double>(this->N - 1) / static_cast<double>(this->N));
  }
};

constexpr double kSigma = 1.0;     // extinction per world unit
constexpr double kL = 1.0;         // slab thickness
constexpr double kUnit = 0.5;      // ScalarOpacityUnitDistance
constexpr double kStep = 0.02;     // camera step (sigma * step = 0.02)
constexpr double kShadowScale = 2.0;
constexpr int kImage = 64;
constexpr int kFrames = 16;

struct Slab
{
  std::vector<float> Voxels = std::vector<float>(64, 1.f);
  float Table[8];
  float StepTable[8];  // the table corrected for the camera step (TransferTable::StepRGBA)
  float ShadowTable[2]; // ... for the shadow step (TransferTable::ShadowAlpha)
  ptv::TraceParams P;
};

void MakeSlab(Slab& s)
{
  const float alpha = static_cast<float>(1.0 - std::exp(-kSigma * kUnit));
  const float c[3] = { 0.8f, 0.5f, 0.25f };
  for (int i = 0; i < 2; ++i)
  {
    s.Table[4 * i + 0] = c[0];
    s.Table[4 * i + 1] = c[1];
    s.Table[4 * i + 2] = c[2];
    s.Table[4 * i + 3] = alpha;
  }
  ptv::TraceParams& p = s.P;
  p = ptv::TraceParams{};
  p.Volume.Scalars = s.Voxels.data();
  p.Volume.Dims[0] = p.Volume.Dims[1] = p.Volume.Dims[2] = 4;
  const float w2i[12] = { 3.f / 40.f, 0.f, 0.f, 1.5f, 0.f, 3.f / 40.f, 0.f, 1.5f, 0.f, 0.f,
    static_cast<float>(3.0 / kL), 0.f };
  for (int i = 0; i < 12; ++i)
  {
    p.Volume.WorldToIndex[i] = w2i[i];
  }
  ptv::ComputeNormalToWorld(p.Volume);
  p.Transfer.RGBA = s.Table;
  p.Transfer.Size = 2;
  p.Transfer.ScalarMin = 0.f;
  p.Transfer.ScalarMax = 2.f;
  p.Occupancy.Distance = nullptr;
  OrthographicAlongZ(p, kImage);
  p.StepWorld = static_cast<float>(kStep);
  p.ShadowStepScale = static_cast<float>(kShadowScale);
  p.UnitDistance = static_cast<float>(kUnit);
  p.Shade = 0;
  p.Diffuse = 1.f;
  p.Scattering = 1;
  p.MaxDistance = nullptr;
  p.Seed = 1234u;
  // As the mapper does (FrameInputs::SetStepTables): opacities corrected once per entry.
  SetStepTables(p, s.StepTable, s.ShadowTable);
}

/// The slab with a key light and occluded environment, traced with the step-corrected tables
/// and without them (each sample corrected on its own, the path taken with gradient opacity):
/// with a constant table both give the same opacities, so every pass must match bit for bit.
bool StepTablesChangeNothing()
{
  Slab s;
  MakeSlab(s);
  s.P.KeyLight.Radiance = ptv::MakeVec3(1.5f, 1.5f, 1.5f);
  s.P.Environment = ptv::MakeVec3(0.5f, 0.7f, 1.0f);
  s.P.AmbientOcclusion = 1;
  ptv::TraceParams perSample = s.P;
  perSample.Transfer.StepRGBA = nullptr;
  perSample.Transfer.ShadowAlpha = nullptr;
  long differ = 0, events = 0;
  for (int f = 0; f < 2; ++f)
  {
    s.P.Frame = perSample.Frame = static_cast<uint32_t>(f + 3000);
    for (int y = 0; y < kImage; ++y)
    {
      for (int x = 0; x < kImage; ++x)
      {
        const ptv::PixelSample a = ptv::TracePixel(s.P, x, y);
        const ptv::PixelSample b = ptv::TracePixel(perSample, x, y);
        events += a.Alpha > 0.f ? 1 : 0;
        differ += a.Alpha != b.Alpha || a.Depth2 != b.Depth2 || a.Radiance.x != b.Radiance.x ||
            a.Radiance.y != b.Radiance.y || a.Radiance.z != b.Radiance.z
          ? 1
          : 0;
      }
    }
  }
  std::printf("step tables vs per-sample correction: %ld of %d samples differ (%ld events)\n",
    differ, 2 * kImage * kImage, events);
  if (differ != 0 || events == 0)
  {
    std::printf("  FAILED: the step-corrected tables changed the estimator\n");
    return false;
  }
  return true;
}

/// E over the shadow jitter of prod (1 - as)^n, n = #{j >= 0 : (j + xi) ds < d}.
double ShadowExpectation(double d, double ds, double oneMinusAs)
{
  const double q = d / ds;
  const double m = std::floor(q);
  const double f = q - m;
  return std::pow(oneMinusAs, m) * (1.0 - f + f * oneMinusAs);
}

/// Exact expectation of the discrete estimator: sum_k T_k a int_0^1 dxi V((k + xi) dt).
template <typename Visibility>
double DiscreteExpectation(Visibility visibility)
{
  const int n = static_cast<int>(std::lround(kL / kStep));
  const double oneMinusA = std::exp(-kSigma * kStep);
  const int nXi = 64;
  double sum = 0.0;
  for (int k = 0; k < n; ++k)
  {
    double inner = 0.0;
    for (int i = 0; i < nXi; ++i)
    {
      inner += visibility((k + (i + 0.5) / nXi) * kStep);
    }
    sum += std::pow(oneMinusA, k) * (1.0 - oneMinusA) * inner / nXi;
  }
  return sum;
}

bool Check(const char* what, double expected, const Stats& s, double discrete, bool* ok)
{
  const double se = s.StdErr();
  const double z = std::fabs(s.Mean - expected) / se;
  const double bias = discrete - expected;
  std::printf("  %-22s expected %.6f measured %.6f  SE %.6f  |diff|/SE %.2f  discrete-estimator "
              "bias %+.2e (%.3f SE)\n",
    what, expected, s.Mean, se, z, bias, std::fabs(bias) / se);
  const bool pass = z <= 3.0 && std::fabs(bias) < 0.25 * se;
  if (!pass)
  {
    std::printf("  FAILED: %s\n", what);
    *ok = false;
  }
  return pass;
}

/// The slab of 1.: the directional light alone (no environment); returns its intensity I.
double MakeDirectLightSlab(Slab& s)
{
  MakeSlab(s);
  s.P.KeyLight.Radiance = ptv::MakeVec3(1.5f, 1.5f, 1.5f);
  s.P.Environment = ptv::MakeVec3(0.f, 0.f, 0.f);
  s.P.AmbientOcclusion = 0;
  return 1.5;
}

/**
 * 4. ExpectedCoverage (ptvIntegrator.h, step 4b) on the slab of 1.: every ray stores the slab's
 * opacity itself, so Alpha equals 1 - exp(-sigma L) on every pixel (float rounding of the 50
 * products: 1e-5), E[Radiance] meets the same closed form (3 SE, discrete bias < SE / 4), and its
 * standard error is below 0.85 of the default estimator's on the same pixels (the coin flip's
 * variance is gone; measured: 0.32, a tenth of the variance).
 */
bool SlabExpectedCoverage()
{
  Slab s;
  const double I = MakeDirectLightSlab(s);
  ptv::TraceParams coverage = s.P;
  coverage.ExpectedCoverage = 1;
  Stats rad, radDefault;
  double alphaMin = 1.0, alphaMax = 0.0;
  for (int f = 0; f < kFrames; ++f)
  {
    s.P.Frame = coverage.Frame = static_cast<uint32_t>(f + 3000);
    for (int y = 0; y < kImage; ++y)
    {
      for (int x = 0; x < kImage; ++x)
      {
        const ptv::PixelSample ps = ptv::TracePixel(coverage, x, y);
        alphaMin = std::min(alphaMin, static_cast<double>(ps.Alpha));
        alphaMax = std::max(alphaMax, static_cast<double>(ps.Alpha));
        rad.Add(ps.Radiance.x);
        radDefault.Add(ptv::TracePixel(s.P, x, y).Radiance.x);
      }
    }
  }
  const double ds = kStep * kShadowScale;
  const double oneMinusAs = std::exp(-kSigma * ds);
  const double jDisc =
    DiscreteExpectation([&](double z) { return ShadowExpectation(z, ds, oneMinusAs); });
  const double j = (1.0 - std::exp(-2.0 * kSigma * kL)) / 2.0;
  const double pAlpha = 1.0 - std::exp(-kSigma * kL);
  std::printf("slab, directional light, ExpectedCoverage (%ld samples):\n", rad.N);
  bool ok = true;
  std::printf("  Alpha on every pixel  expected %.6f measured %.6f .. %.6f\n", pAlpha, alphaMin,
    alphaMax);
  if (!(std::fabs(alphaMin - pAlpha) < 1e-5 && std::fabs(alphaMax - pAlpha) < 1e-5))
  {
    std::printf("  FAILED: Alpha is not the slab's opacity on every pixel\n");
    ok = false;
  }
  const double scale = s.Table[0] * I;
  Check("E[Radiance.r]", scale * j, rad, scale * jDisc, &ok);
  std::printf("  SE of the radiance: %.6f (default estimator %.6f)\n", rad.StdErr(),
    radDefault.StdErr());
  if (!(rad.StdErr() < 0.85 * radDefault.StdErr()))
  {
    std::printf("  FAILED: ExpectedCoverage does not lower the radiance's variance\n");
    ok = false;
  }
  return ok;
}

/**
 * CoverageMarch (ptvIntegrator.h, step 4c) on the slab: Coverage is the slab's opacity
 * 1 - exp(-sigma L) on every pixel (0.63, below the march's cutoff, so every ray crosses the
 * whole slab; float rounding of the 50 products: 1e-5), and every other field is bit-identical
 * to the default's (the march past the event draws no random numbers). Without it, Coverage is
 * the sample's Alpha; so it is with Scattering off (first-hit events).
 */
bool SlabCoverageMarch()
{
  Slab s;
  MakeDirectLightSlab(s);
  ptv::TraceParams march = s.P;
  march.CoverageMarch = 1;
  ptv::TraceParams firstHit = march;
  firstHit.Scattering = 0;
  const double pAlpha = 1.0 - std::exp(-kSigma * kL);
  double coverageMin = 1.0, coverageMax = 0.0;
  long differ = 0, notAlpha = 0;
  for (int f = 0; f < kFrames; ++f)
  {
    s.P.Frame = march.Frame = firstHit.Frame = static_cast<uint32_t>(f + 4000);
    for (int y = 0; y < kImage; ++y)
    {
      for (int x = 0; x < kImage; ++x)
      {
        const ptv::PixelSample m = ptv::TracePixel(march, x, y);
        const ptv::PixelSample d = ptv::TracePixel(s.P, x, y);
        const ptv::PixelSample h = ptv::TracePixel(firstHit, x, y);
        coverageMin = std::min(coverageMin, static_cast<double>(m.Coverage));
        coverageMax = std::max(coverageMax, static_cast<double>(m.Coverage));
        const float a[] = { m.Radiance.x, m.Radiance.y, m.Radiance.z, m.Alpha, m.Albedo.x,
          m.Depth1, m.Position1.z, m.Normal1.z, m.Depth2, m.Position2.z, m.Normal2.z };
        const float b[] = { d.Radiance.x, d.Radiance.y, d.Radiance.z, d.Alpha, d.Albedo.x,
          d.Depth1, d.Position1.z, d.Normal1.z, d.Depth2, d.Position2.z, d.Normal2.z };
        differ += std::memcmp(a, b, sizeof(a)) != 0 ? 1 : 0;
        notAlpha += (d.Coverage != d.Alpha || h.Coverage != h.Alpha) ? 1 : 0;
      }
    }
  }
  std::printf("slab, CoverageMarch: Coverage expected %.6f measured %.6f .. %.6f; samples "
              "differing from the default's %ld; without the march, Coverage != Alpha %ld\n",
    pAlpha, coverageMin, coverageMax, differ, notAlpha);
  const bool ok = std::fabs(coverageMin - pAlpha) < 1e-5 &&
    std::fabs(coverageMax - pAlpha) < 1e-5 && differ == 0 && notAlpha == 0;
  if (!ok)
  {
    std::printf("  FAILED: CoverageMarch\n");
  }
  return ok;
}

/**
 * 1., and with @a pieces 3.: the slab as two pieces of a distributed volume
 * (TraceParams::CameraBox), split at z = L/2 (index 1.5). Each piece traces the same camera
 * rays with its own events (PieceStream 1, 2), shadow rays cross the whole slab (its ghost layer
 * is the other half), and OverSample composites them front first. The composite must meet the
 * same closed forms (the pieces share the whole ray's sample grid), and the front piece alone
 * has E[Alpha] = 1 - exp(-sigma L / 2) (its camera rays stop at its box).
 */
bool SlabDirectLight(bool pieces)
{
  Slab s;
  const double I = MakeDirectLightSlab(s);
  ptv::TraceParams front = s.P, back = s.P;
  if (pieces)
  {
    const float whole[6] = { 0.f, 3.f, 0.f, 3.f, 0.f, 3.f };
    for (int i = 0; i < 6; ++i)
    {
      front.WholeBox[i] = back.WholeBox[i] = whole[i];
      front.CameraBox[i] = back.CameraBox[i] = whole[i];
    }
    front.CameraBoxed = back.CameraBoxed = 1;
    front.CameraBox[5] = 1.5f; // z in [0, L/2]
    back.CameraBox[4] = 1.5f;  // z in [L/2, L]
    front.PieceStream = 1u;
    back.PieceStream = 2u;
  }
  Stats alpha, frontAlpha, rad[3];
  for (int f = 0; f < kFrames; ++f)
  {
    s.P.Frame = front.Frame = back.Frame = static_cast<uint32_t>(pieces ? f + 2000 : f);
    for (int y = 0; y < kImage; ++y)
    {
      for (int x = 0; x < kImage; ++x)
      {
        ptv::PixelSample ps;
        if (pieces)
        {
          const ptv::PixelSample a = ptv::TracePixel(front, x, y);
          ps = ptv::OverSample(a, ptv::TracePixel(back, x, y), s.P.Camera.FarDistance);
          frontAlpha.Add(a.Alpha);
        }
        else
        {
          ps = ptv::TracePixel(s.P, x, y);
        }
        alpha.Add(ps.Alpha);
        rad[0].Add(ps.Radiance.x);
        rad[1].Add(ps.Radiance.y);
        rad[2].Add(ps.Radiance.z);
      }
    }
  }
  const double ds = kStep * kShadowScale;
  const double oneMinusAs = std::exp(-kSigma * ds);
  const double jDisc =
    DiscreteExpectation([&](double z) { return ShadowExpectation(z, ds, oneMinusAs); });
  const double j = (1.0 - std::exp(-2.0 * kSigma * kL)) / 2.0;
  std::printf("slab%s, directional light (sigma L = %g, sigma dt = %g, %ld samples):\n",
    pieces ? " in two pieces (z < L/2, z > L/2), composited" : "", kSigma * kL, kSigma * kStep,
    alpha.N);
  bool ok = true;
  if (pieces)
  {
    const double pHalf = 1.0 - std::exp(-kSigma * kL / 2.0);
    Check("front E[Alpha]", pHalf, frontAlpha, pHalf, &ok);
  }
  const double pAlpha = 1.0 - std::exp(-kSigma * kL);
  Check("E[Alpha]", pAlpha, alpha, pAlpha, &ok);
  const char* names[3] = { "E[Radiance.r]", "E[Radiance.g]", "E[Radiance.b]" };
  for (int c = 0; c < 3; ++c)
  {
    const double scale = s.Table[c] * I;
    Check(names[c], scale * j, rad[c], scale * jDisc, &ok);
  }
  return ok;
}

bool SlabEnvironment()
{
  Slab s;
  MakeSlab(s);
  const double E[3] = { 0.5, 0.7, 1.0 };
  s.P.KeyLight.Radiance = ptv::MakeVec3(0.f, 0.f, 0.f);
  s.P.Environment = ptv::MakeVec3(0.5f, 0.7f, 1.0f);
  s.P.AmbientOcclusion = 1;
  Stats alpha, rad[3];
  for (int f = 0; f < kFrames; ++f)
  {
    s.P.Frame = static_cast<uint32_t>(f + 1000);
    for (int y = 0; y < kImage; ++y)
    {
      for (int x = 0; x < kImage; ++x)
      {
        const ptv::PixelSample ps = ptv::TracePixel(s.P, x, y);
        alpha.Add(ps.Alpha);
        rad[0].Add(ps.Radiance.x);
        rad[1].Add(ps.Radiance.y);
        rad[2].Add(ps.Radiance.z);
      }
    }
  }
  // Closed form J (midpoint rule in mu).
  const double sl = kSigma * kL;
  const int nMu = 200000;
  double j = 0.0;
  for (int i = 0; i < nMu; ++i)
  {
    const double mu = (i + 0.5) / nMu;
    const double a = mu / (1.0 + mu) * (1.0 - std::exp(-sl * (1.0 + mu) / mu));
    const double b = mu * std::exp(-sl) * -std::expm1(-sl * (1.0 - mu) / mu) / (1.0 - mu);
    j += 0.5 * (a + b) / nMu;
  }
  // Exact expectation of the discrete estimator (same quadrature in mu, both hemispheres).
  const double ds = kStep * kShadowScale;
  const double oneMinusAs = std::exp(-kSigma * ds);
  const int nMuDisc = 2000;
  const double jDisc = DiscreteExpectation([&](double z) {
    double v = 0.0;
    for (int i = 0; i < nMuDisc; ++i)
    {
      const double mu = (i + 0.5) / nMuDisc;
      v += ShadowExpectation((kL - z) / mu, ds, oneMinusAs) +
        ShadowExpectation(z / mu, ds, oneMinusAs);
    }
    return 0.5 * v / nMuDisc;
  });
  std::printf("slab, environment only (AO, uniform sphere; J = %.6f):\n", j);
  bool ok = true;
  const double pAlpha = 1.0 - std::exp(-kSigma * kL);
  Check("E[Alpha]", pAlpha, alpha, pAlpha, &ok);
  const char* names[3] = { "E[Radiance.r]", "E[Radiance.g]", "E[Radiance.b]" };
  for (int c = 0; c < 3; ++c)
  {
    const double scale = s.Table[c] * E[c];
    Check(names[c], scale * j, rad[c], scale * jDisc, &ok);
  }
  return ok;
}

bool SmallClosedForms()
{
  bool ok = true;
  // Opacity correction: two half steps compose to one unit step; limits.
  for (float a : { 0.001f, 0.3f, 0.9f })
  {
    const float h = ptv::CorrectOpacity(a, 0.5f);
    const float twice = 1.f - (1.f - h) * (1.f - h);
    if (std::fabs(twice - a) > 1e-6f || std::fabs(ptv::CorrectOpacity(a, 1.f) - a) > 1e-6f)
    {
      std::printf("  FAILED: CorrectOpacity composition at alpha %g\n", a);
      ok = false;
    }
  }
  // Step tables: at an entry the corrected opacity itself, between entries the linear
  // interpolation of the corrected entries (0.1 and 0.9 over scalars 0..2, a step of 0.5 units).
  {
    const float rgba[8] = { 1.f, 0.f, 0.f, 0.1f, 0.f, 1.f, 0.f, 0.9f };
    float stepRGBA[8], shadowAlpha[2];
    ptv::TransferTable tf{};
    tf.RGBA = rgba;
    tf.Size = 2;
    tf.ScalarMin = 0.f;
    tf.ScalarMax = 2.f;
    ptv::BuildStepTables(tf, 0.5f, 1.f, stepRGBA, shadowAlpha);
    const float a0 = ptv::CorrectOpacity(0.1f, 0.5f), a1 = ptv::CorrectOpacity(0.9f, 0.5f);
    const ptv::TransferSample mid = ptv::LookupRGBA(tf, stepRGBA, 1.f);
    if (ptv::LookupRGBA(tf, stepRGBA, 0.f).Opacity != a0 ||
      ptv::LookupRGBA(tf, stepRGBA, 2.f).Opacity != a1 ||
      std::fabs(mid.Opacity - 0.5f * (a0 + a1)) > 1e-6f || std::fabs(mid.Color.x - 0.5f) > 1e-6f ||
      std::fabs(ptv::LookupValue(tf, shadowAlpha, 0.5f) - (0.75f * 0.1f + 0.25f * 0.9f)) > 1e-6f ||
      ptv::LookupValue(tf, shadowAlpha, std::nanf("")) != 0.f)
    {
      std::printf("  FAILED: step-corrected table lookups\n");
      ok = false;
    }
  }
  if (ptv::CorrectOpacity(0.f, 2.f) != 0.f || ptv::CorrectOpacity(-1.f, 2.f) != 0.f ||
    ptv::CorrectOpacity(1.f, 0.1f) != 1.f || ptv::CorrectOpacity(2.f, 0.1f) != 1.f)
  {
    std::printf("  FAILED: CorrectOpacity limits\n");
    ok = false;
  }

  // Duff et al. basis is orthonormal, including the n.z = -1 branch.
  const ptv::Vec3 normals[4] = { ptv::MakeVec3(0.f, 0.f, 1.f), ptv::MakeVec3(0.f, 0.f, -1.f),
    ptv::Normalize(ptv::MakeVec3(1.f, -2.f, 0.5f)),
    ptv::Normalize(ptv::MakeVec3(0.3f, 0.1f, -2.f)) };
  for (const ptv::Vec3& n : normals)
  {
    ptv::Vec3 b1, b2;
    ptv::OrthonormalBasis(n, b1, b2);
    const double err = std::fabs(ptv::Dot(b1, b2)) + std::fabs(ptv::Dot(b1, n)) +
      std::fabs(ptv::Dot(b2, n)) + std::fabs(ptv::Length(b1) - 1.f) +
      std::fabs(ptv::Length(b2) - 1.f) + ptv::Length(ptv::Cross(b1, b2) - n);
    if (err > 1e-5)
    {
      std::printf("  FAILED: orthonormal basis error %g\n", err);
      ok = false;
    }
  }

  // Sampling moments: cosine hemisphere E[n.w] = 2/3, E[(n.w)^2] = 1/2; sphere E[w] = 0,
  // E[w_z^2] = 1/3.
  ptv::Rng rng = ptv::MakeRng(7u, 0u, 1u);
  Stats c1, c2, sx, sz2;
  const ptv::Vec3 n = normals[3];
  bool below = false;
  for (int i = 0; i < 200000; ++i)
  {
    const float u1 = ptv::NextFloat(rng);
    const float u2 = ptv::NextFloat(rng);
    const ptv::Vec3 w = ptv::SampleCosineHemisphere(n, u1, u2);
    const double cw = ptv::Dot(n, w);
    below = below || cw < -1e-6 || std::fabs(ptv::Length(w) - 1.f) > 1e-5f;
    c1.Add(cw);
    c2.Add(cw * cw);
    const ptv::Vec3 s = ptv::SampleUniformSphere(u1, u2);
    sx.Add(s.x);
    sz2.Add(s.z * s.z);
  }
  struct
  {
    const char* Name;
    const Stats* S;
    double Expected;
  } moments[4] = { { "cosine E[n.w]", &c1, 2.0 / 3.0 }, { "cosine E[(n.w)^2]", &c2, 0.5 },
    { "sphere E[w.x]", &sx, 0.0 }, { "sphere E[w.z^2]", &sz2, 1.0 / 3.0 } };
  std::printf("sampling moments (200000 samples):\n");
  for (const auto& m : moments)
  {
    const double z = std::fabs(m.S->Mean - m.Expected) / m.S->StdErr();
    std::printf("  %-22s expected %.6f measured %.6f  SE %.6f  |diff|/SE %.2f\n", m.Name,
      m.Expected, m.S->Mean, m.S->StdErr(), z);
    ok = ok && z <= 3.0;
  }
  if (below)
  {
    std::printf("  FAILED: cosine sample below the hemisphere or not unit length\n");
    ok = false;
  }

  // Linear field f = 2 i + 3 j - k: trilinear is exact, the interior gradient is (2, 3, -1) per
  // voxel and the world gradient is M^T (2, 3, -1) for index = M world + t.
  std::vector<float> lin(5 * 6 * 7);
  for (int k = 0; k < 7; ++k)
    for (int j = 0; j < 6; ++j)
      for (int i = 0; i < 5; ++i)
        lin[i + 5 * (j + 6 * k)] = static_cast<float>(2 * i + 3 * j - k);
  ptv::VolumeGrid g{};
  g.Scalars = lin.data();
  g.Dims[0] = 5;
  g.Dims[1] = 6;
  g.Dims[2] = 7;
  const float w2i[12] = { 0.f, 2.f, 0.f, 1.f, -0.5f, 0.f, 0.f, 2.f, 0.f, 0.f, 4.f, 3.f };
  for (int i = 0; i < 12; ++i)
    g.WorldToIndex[i] = w2i[i];
  ptv::ComputeNormalToWorld(g);
  const ptv::Vec3 pIdx = ptv::MakeVec3(1.25f, 2.5f, 3.75f);
  const float v = ptv::SampleTrilinear(g, pIdx);
  const ptv::Vec3 gi = ptv::GradientIndex(g, pIdx);
  const ptv::Vec3 gw = ptv::MultiplyMatrix3(g.NormalToWorld, gi);
  // df/dworld = (df/di)(di/dw) = (2,3,-1) M = (3 * -0.5, 2 * 2, -1 * 4) = (-1.5, 4, -4).
  const double err = std::fabs(v - (2 * 1.25 + 3 * 2.5 - 3.75)) +
    ptv::Length(gi - ptv::MakeVec3(2.f, 3.f, -1.f)) +
    ptv::Length(gw - ptv::MakeVec3(-1.5f, 4.f, -4.f));
  const float clampedLow = ptv::SampleTrilinear(g, ptv::MakeVec3(-3.f, -1.f, -2.f));
  const float clampedHigh = ptv::SampleTrilinear(g, ptv::MakeVec3(9.f, 9.f, 9.f));
  const float nearest = ptv::SampleNearest(g, ptv::MakeVec3(1.4f, 2.6f, 3.2f));
  std::printf("linear field: value/gradient/world-gradient error %.2e, clamp %g %g, nearest %g\n",
    err, clampedLow, clampedHigh, nearest);
  if (err > 1e-5 || clampedLow != 0.f || clampedHigh != 2 * 4 + 3 * 5 - 6 ||
    nearest != 2 * 1 + 3 * 3 - 3)
  {
    std::printf("  FAILED: volume sampling\n");
    ok = false;
  }
  return ok;
}
}

int TestPTVKernelSlab(int, char*[])
{
  bool ok = SmallClosedForms();
  ok = SlabDirectLight(false) && ok;
  ok = SlabEnvironment() && ok;
  ok = SlabDirectLight(true) && ok;
  ok = SlabExpectedCoverage() && ok;
  ok = SlabCoverageMarch() && ok;
  ok = StepTablesChangeNothing() && ok;
  std::printf(ok ? "TestPTVKernelSlab passed\n" : "TestPTVKernelSlab FAILED\n");
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
