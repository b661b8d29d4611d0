// Every failure of vtkPTVOpenVDBReader / vtkPTVOpenVDBWriter is an error event whose text names
// the offending value; the output stays empty, nothing crashes, no partial file is left, and the
// same object works again afterwards.
//   reader: empty FileName, missing file, corrupt file, truncated file, unknown grid name (the
//           message lists the grids), vec3s grid, file without scalar grids, non-uniform /
//           rotated / frustum transforms (the message names the map type), empty grid;
//           damaged sizes/offsets in the header, metadata and grid descriptor ("truncated or
//           corrupt", found before OpenVDB reads), a corrupt compressed-block size.
//   writer: no input, no scalars, short scalars, 3-component scalars, non-uniform spacing,
//           rotated direction matrix, unwritable folder.
#include "ptvTestCheck.h"
#include "ptvTestVDBWriters.h"
#include "ptvOpenVDBGrid.h"
#include "vtkCommand.h"
#include "vtkExecutive.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPTVOpenVDBReader.h"
#include "vtkPTVOpenVDBWriter.h"
#include "vtkPointData.h"
#include "vtkShortArray.h"
#include "vtkSmartPointer.h"
#include "vtkTestErrorObserver.h"
#include "vtkTestUtilities.h"
#include "vtksys/SystemTools.hxx"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include <unistd.h> // for getpid

namespace
{

// Observes errors and warnings of an algorithm and of its executive.
struct Observed
{
  vtkNew<vtkTest::ErrorObserver> Observer;

  void Attach(vtkAlgorithm* algorithm)
  {
    for (vtkObject* object : { static_cast<vtkObject*>(algorithm),
           static_cast<vtkObject*>(algorithm->GetExecutive()) })
    {
      object->AddObserver(vtkCommand::ErrorEvent, this->Observer);
      object->AddObserver(vtkCommand::WarningEvent, this->Observer);
    }
  }

  // An error was reported and its text contains every one of @a needles.
  void Expect(const std::string& label, const std::vector<std::string>& needles)
  {
    const std::string text = this->Observer->GetErrorMessage();
    Check(this->Observer->GetError(), label + ": an error must be reported");
    for (const std::string& needle : needles)
    {
      Check(text.find(needle) != std::string::npos,
        label + ": the error must mention \"" + needle + "\"; got: " + text);
    }
    // Print only the first message's text line, without VTK's "ERROR: In <file>, line <n>" line
    // (ctest fails any test whose output contains that).
    std::string first = text.substr(text.find('\n') + 1);
    first = first.substr(0, first.find('\n'));
    std::cout << label << ": reported as expected: " << first << "\n";
    this->Observer->Clear();
  }

  void ExpectNone(const std::string& label)
  {
    Check(!this->Observer->GetError() && !this->Observer->GetWarning(),
      label + ": no error/warning expected; got: " + this->Observer->GetErrorMessage() +
        this->Observer->GetWarningMessage());
    this->Observer->Clear();
  }
};

// Read @a file (grid @a grid) expecting failure, an empty output and a message naming @a needles.
void ExpectReadError(const std::string& label, const char* file, const char* grid,
  const std::vector<std::string>& needles)
{
  vtkNew<vtkPTVOpenVDBReader> reader;
  Observed observed;
  observed.Attach(reader);
  reader->SetFileName(file);
  reader->SetGridName(grid);
  reader->Update();
  observed.Expect(label, needles);
  Check(reader->GetOutput()->GetNumberOfPoints() == 0, label + ": output must stay empty");
  Check(reader->GetOutput()->GetPointData()->GetNumberOfArrays() == 0,
    label + ": output must have no arrays");
}

vtkSmartPointer<vtkImageData> MakeImage(int components, int type)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(4, 3, 2);
  image->SetSpacing(0.5, 0.5, 0.5);
  image->AllocateScalars(type, components);
  vtkDataArray* scalars = image->GetPointData()->GetScalars();
  scalars->SetName("values");
  for (vtkIdType n = 0; n < scalars->GetNumberOfValues(); ++n)
  {
    scalars->SetComponent(n / components, static_cast<int>(n % components), 1.0 + n % 5);
  }
  return image;
}

// Write @a image to @a file expecting failure, a message naming @a needles and no file.
void ExpectWriteError(const std::string& label, vtkImageData* image, const std::string& file,
  const std::vector<std::string>& needles)
{
  vtkNew<vtkPTVOpenVDBWriter> writer;
  Observed observed;
  observed.Attach(writer);
  if (image)
  {
    writer->SetInputData(image);
  }
  writer->SetFileName(file.c_str());
  Check(writer->Write() == 0, label + ": Write() must return 0");
  observed.Expect(label, needles);
  Check(!vtksys::SystemTools::FileExists(file), label + ": no file may be created: " + file);
}

void ReaderErrors(const std::string& dir)
{
  // A valid file to damage and to read after the errors.
  const std::string good = dir + "/ptv_errors_good.vdb";
  {
    vtkNew<vtkPTVOpenVDBWriter> writer;
    auto image = vtkSmartPointer<vtkImageData>::New();
    image->SetDimensions(32, 32, 32);
    image->AllocateScalars(VTK_FLOAT, 1);
    auto* values = vtkFloatArray::SafeDownCast(image->GetPointData()->GetScalars());
    for (vtkIdType n = 0; n < values->GetNumberOfValues(); ++n)
    {
      values->SetValue(n, 1.0f + static_cast<float>(n % 97) * 0.25f);
    }
    writer->SetInputData(image);
    writer->SetFileName(good.c_str());
    Check(writer->Write() == 1, "writing the reference file must succeed");
  }

  ExpectReadError("empty FileName", "", nullptr, { "FileName" });
  ExpectReadError("null FileName", nullptr, nullptr, { "FileName" });

  const std::string missing = dir + "/ptv_errors_no_such_file.vdb";
  ExpectReadError("missing file", missing.c_str(), nullptr, { missing, "does not exist" });

  // Random bytes.
  const std::string corrupt = dir + "/ptv_errors_corrupt.vdb";
  {
    std::mt19937 rng(1234);
    std::ofstream out(corrupt, std::ios::binary);
    for (int n = 0; n < 4096; ++n)
    {
      out.put(static_cast<char>(rng() & 0xff));
    }
  }
  ExpectReadError("corrupt file", corrupt.c_str(), nullptr, { corrupt });
  Check(vtkPTVOpenVDBReader::CanReadFile(corrupt.c_str()) == 0,
    "CanReadFile must reject random bytes");

  // The first half of a valid file.
  const std::string truncated = dir + "/ptv_errors_truncated.vdb";
  {
    std::ifstream in(good, std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    Check(bytes.size() > 1000, "the reference file must have some size");
    std::ofstream out(truncated, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size() / 2));
  }
  ExpectReadError(
    "truncated file", truncated.c_str(), nullptr, { truncated, "truncated or corrupt" });
  Check(vtkPTVOpenVDBReader::CanReadFile(truncated.c_str()) == 0,
    "CanReadFile must reject a truncated file");

  // Layout checks before OpenVDB reads (fuzz_openvdb_reader findings): sizes and offsets in the
  // header, the metadata and the grid descriptors that OpenVDB would trust. Each damaged copy
  // of the good file must give a "truncated or corrupt" error at once (OpenVDB itself
  // allocated gigabytes for the 128-byte head, or read past the end).
  {
    std::ifstream in(good, std::ios::binary);
    const std::vector<char> bytes(
      (std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    // Layout of a file from vtkPTVOpenVDBWriter (format 224): 8-byte magic, 3 uint32 versions,
    // 1 byte "has grid offsets", 36-byte UUID, file metadata count (0), grid count (1), then the
    // descriptor: name (uint32 7 + "density"), type (uint32 16 + "Tree_float_5_4_3"), parent
    // (uint32 0), int64 grid/block/end offsets; the grid's compression flags and metadata next.
    const std::size_t metaCount = 8 + 12 + 1 + 36;
    const std::size_t nameLength = metaCount + 8;
    const std::size_t typeLength = nameLength + 4 + 7;
    const std::size_t offsets = typeLength + 4 + 16 + 4;
    const std::size_t gridMeta = offsets + 24 + 4; // the grid's metadata count
    auto damaged = [&](const std::string& name, std::size_t size,
                     const std::vector<std::pair<std::size_t, std::uint32_t>>& patches) {
      std::vector<char> copy(bytes.begin(), bytes.begin() + std::min(size, bytes.size()));
      for (const auto& patch : patches)
      {
        if (patch.first + 4 <= copy.size())
        {
          std::memcpy(copy.data() + patch.first, &patch.second, 4);
        }
      }
      const std::string file = dir + "/ptv_errors_" + name + ".vdb";
      std::ofstream out(file, std::ios::binary);
      out.write(copy.data(), static_cast<std::streamsize>(copy.size()));
      return file;
    };
    std::uint32_t check = 0;
    std::memcpy(&check, bytes.data() + nameLength, 4);
    Check(check == 7 && bytes.size() > gridMeta + 4 &&
        std::string(bytes.data() + nameLength + 4, 7) == "density",
      "the reference file must have the expected layout (see the comment)");
    const std::string head = damaged("head128", 128, {});
    ExpectReadError("first 128 bytes", head.c_str(), nullptr, { head, "truncated or corrupt" });
    Check(vtkPTVOpenVDBReader::CanReadFile(head.c_str()) == 0,
      "CanReadFile must reject the first 128 bytes");
    const std::string longName = damaged("long_name", bytes.size(), { { nameLength, 0xFFFFFFF0u } });
    ExpectReadError("grid name length 4 GB", longName.c_str(), nullptr,
      { longName, "truncated or corrupt", "cut short" });
    const std::string manyMeta =
      damaged("many_metadata", bytes.size(), { { metaCount, 0x7FFFFFFFu } });
    ExpectReadError("2^31 metadata entries", manyMeta.c_str(), nullptr,
      { manyMeta, "truncated or corrupt", "entries" });
    const std::string farEnd = damaged("end_offset", bytes.size(), { { offsets + 16, 0x7FFFFFFFu } });
    ExpectReadError(
      "end offset past the file", farEnd.c_str(), nullptr, { farEnd, "truncated or corrupt" });
    const std::string oldVersion = damaged("version0", bytes.size(), { { 8, 0u } });
    ExpectReadError("format version 0", oldVersion.c_str(), nullptr,
      { oldVersion, "format version 0", "older than OpenVDB 3.0" });
    const std::string noOffsets = damaged("no_offsets", bytes.size(), { { 20, 0u } });
    ExpectReadError("no grid offsets", noOffsets.c_str(), nullptr, { noOffsets, "no grid offsets" });
    const std::string gridMetaCount =
      damaged("grid_metadata", bytes.size(), { { gridMeta, 0x10000000u } });
    ExpectReadError("grid metadata count", gridMetaCount.c_str(), nullptr,
      { gridMetaCount, "truncated or corrupt", "'density'" });

    // Counts inside values that OpenVDB parses itself (fuzz_openvdb_reader): the leaf count of
    // the grid's delayed-load metadata (a 7.4 GB allocation) and the root node's tile count
    // (4 billion reads past the end of the file). The writer's file holds "file_delayed_load",
    // then uint32 13 + "__delayedload", the uint32 value size and the uint32 leaf count; and
    // after the transform the topology: int32 1 (buffers), float 0 (background), uint32 0 tiles,
    // uint32 1 child.
    const std::string delayed = "file_delayed_load__delayedload";
    std::vector<char> key(delayed.begin(), delayed.begin() + 17);
    const char typeTag[] = { 13, 0, 0, 0 };
    key.insert(key.end(), typeTag, typeTag + 4);
    key.insert(key.end(), delayed.begin() + 17, delayed.end());
    const auto at = std::search(bytes.begin(), bytes.end(), key.begin(), key.end());
    Check(at != bytes.end(), "the reference file must hold delayed-load metadata");
    const std::size_t leafCount = static_cast<std::size_t>(at - bytes.begin()) + key.size() + 4;
    const std::string leaves = damaged("delayed_load", bytes.size(), { { leafCount, 0x7FFFFFFFu } });
    ExpectReadError("delayed-load leaf count", leaves.c_str(), nullptr,
      { leaves, "truncated or corrupt", "2147483647 leaves" });
    const std::string mapName = "UniformScaleTranslateMap";
    const auto map = std::search(bytes.begin(), bytes.end(), mapName.begin(), mapName.end());
    const char rootHead[] = { 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0 };
    const auto root = std::search(map, bytes.end(), rootHead, rootHead + sizeof(rootHead));
    Check(map != bytes.end() && root != bytes.end(), "the reference file must hold the root");
    const std::size_t tileCount = static_cast<std::size_t>(root - bytes.begin()) + 8;
    const std::string tiles = damaged("root_tiles", bytes.size(), { { tileCount, 0xFFFFFFF0u } });
    ExpectReadError("root tile count", tiles.c_str(), nullptr,
      { tiles, "truncated or corrupt", "4294967280 tiles" });
    const std::string children = damaged("root_children", bytes.size(), { { tileCount + 4, 4096u } });
    ExpectReadError("root child count", children.c_str(), nullptr,
      { children, "truncated or corrupt", "4096 child nodes" });
  }

  // Every storage OpenVDB writes passes the tree walk and reads the same voxels: raw, zip,
  // blosc, each with and without active-mask compression (all value-block layouts of
  // io::readCompressedValues occur in the grid), as floats and as half floats (type suffix
  // "_HalfFloat"; the grid's values are exact halves).
  {
    std::vector<float> first;
    for (const unsigned int compression : { 0u, 1u, 2u, 3u, 4u, 6u })
    {
      for (const bool asHalf : { false, true })
      {
        const std::string name = "storage " + std::to_string(compression) +
          (asHalf ? " half" : " float");
        const std::string file = dir + "/ptv_errors_storage_" + std::to_string(compression) +
          (asHalf ? "_half" : "") + ".vdb";
        std::string error;
        Check(ptvtest::WriteTestStorageGrid(file, "density", compression, asHalf, error),
          name + ": WriteTestStorageGrid: " + error);
        vtkNew<vtkPTVOpenVDBReader> reader;
        Observed observed;
        observed.Attach(reader);
        reader->SetFileName(file.c_str());
        reader->Update();
        observed.ExpectNone(name);
        vtkFloatArray* values =
          vtkFloatArray::SafeDownCast(reader->GetOutput()->GetPointData()->GetScalars());
        Check(values && values->GetNumberOfTuples() == 72 * 20 * 20, name + ": 72 x 20 x 20");
        if (!values)
        {
          continue;
        }
        std::vector<float> read(values->GetPointer(0), values->GetPointer(0) + 72 * 20 * 20);
        if (first.empty())
        {
          first = read;
          Check(std::count(read.begin(), read.end(), 2.0f) >= 8 * 8 * 8 &&
              std::count(read.begin(), read.end(), -1.0f) > 0,
            name + ": the tile and the inactive values are read");
        }
        Check(read == first, name + ": the same voxels as raw storage");
      }
    }
  }

  // A compressed block inside the grid's topology declaring ~140 TB (a one-byte mutation found by
  // fuzz_openvdb_reader; Testing/Data/vdb_corrupt_block_size.vdb). OpenVDB would allocate that
  // size before reading; the tree walk (ptvOpenVDBTree.cxx) refuses the file first, so this now
  // runs under AddressSanitizer too.
  {
    std::string source = __FILE__;
    source = source.substr(0, source.find_last_of("/\\"));
    const std::string blockSize = source + "/../Data/vdb_corrupt_block_size.vdb";
    Check(vtksys::SystemTools::FileExists(blockSize), "missing test file " + blockSize);
    ExpectReadError(
      "corrupt block size", blockSize.c_str(), nullptr, { blockSize, "truncated or corrupt" });
    // An uncompressed value block declaring more bytes than its values hold: OpenVDB 10.0's
    // io::bloscFromStream reads that many bytes into the values' buffer before comparing
    // (heap-buffer-overflow, fuzz_openvdb_reader; Testing/Data/vdb_blosc_overflow.vdb).
    const std::string overflow = source + "/../Data/vdb_blosc_overflow.vdb";
    ExpectReadError("blosc overflow", overflow.c_str(), nullptr,
      { overflow, "an uncompressed value block declares", "for 27 values of 4 bytes" });
    // Bounding-box metadata spanning 335544326 x 1879039037 x 48 voxels: the product of the
    // extents overflowed a 64-bit integer (UBSan, fuzz_openvdb_reader); now the voxel limit says
    // so (Testing/Data/vdb_huge_bbox.vdb).
    const std::string hugeBox = source + "/../Data/vdb_huge_bbox.vdb";
    ExpectReadError("huge bounding box", hugeBox.c_str(), nullptr,
      { hugeBox, "335544326 x 1879039037 x 48 voxels", "MaximumNumberOfVoxels" });
  }

  // Unknown grid: the message lists what the file has.
  ExpectReadError("missing grid", good.c_str(), "nosuchgrid", { "'nosuchgrid'", "'density'" });

  // A vec3s grid, and a file with no scalar grid at all.
  const std::string vectors = dir + "/ptv_errors_vec3.vdb";
  std::string error;
  Check(ptvtest::WriteTestVectorGrid(vectors, "velocity", "", error),
    "WriteTestVectorGrid failed: " + error);
  ExpectReadError("vec3s grid", vectors.c_str(), "velocity",
    { "grid 'velocity' is of type vec3s; only scalar float/double grids are supported" });
  ExpectReadError("no scalar grid", vectors.c_str(), nullptr, { "no scalar", "'velocity'" });

  // Transforms that a dense image cannot represent; the message names the OpenVDB map type.
  const struct
  {
    const char* Kind;
    const char* Map;
  } transforms[] = { { "nonuniform", "ScaleMap" }, { "rotated", "AffineMap" },
    { "frustum", "NonlinearFrustumMap" } };
  for (const auto& t : transforms)
  {
    const std::string file = dir + "/ptv_errors_" + t.Kind + ".vdb";
    Check(ptvtest::WriteTestTransformedGrid(file, "warped", t.Kind, error),
      std::string("WriteTestTransformedGrid(") + t.Kind + ") failed: " + error);
    ExpectReadError(std::string(t.Kind) + " transform", file.c_str(), nullptr,
      { "'warped'", t.Map, "only uniform-scale linear transforms are supported" });
  }

  // A grid without active voxels: all values equal the background.
  const std::string empty = dir + "/ptv_errors_empty.vdb";
  {
    vtkNew<vtkPTVOpenVDBWriter> writer;
    auto image = vtkSmartPointer<vtkImageData>::New();
    image->SetDimensions(5, 5, 5);
    image->AllocateScalars(VTK_FLOAT, 1);
    image->GetPointData()->GetScalars()->Fill(3.0);
    writer->SetInputData(image);
    writer->SetFileName(empty.c_str());
    writer->SetGridName("nothing");
    writer->SetBackground(3.0);
    Check(writer->Write() == 1, "writing an all-background volume must succeed");
  }
  ExpectReadError("empty grid", empty.c_str(), nullptr, { "'nothing'", "no active voxels" });

  // MaximumNumberOfVoxels: a read of a larger dense box is refused before anything is allocated
  // (fuzz_openvdb_reader: two far-apart voxels made a 13 GB box); a sub-extent within the limit
  // still reads.
  {
    vtkNew<vtkPTVOpenVDBReader> limited;
    Observed observed;
    observed.Attach(limited);
    limited->SetFileName(good.c_str());
    limited->SetMaximumNumberOfVoxels(1000);
    limited->Update();
    observed.Expect("voxel limit",
      { "32 x 32 x 32 voxels", "MaximumNumberOfVoxels (1000)", "'density'" });
    Check(limited->GetOutput()->GetNumberOfPoints() == 0, "voxel limit: no output");
    vtkNew<vtkPTVOpenVDBReader> piece;
    observed.Attach(piece);
    piece->SetFileName(good.c_str());
    piece->SetMaximumNumberOfVoxels(1000);
    const int extent[6] = { 0, 9, 0, 9, 0, 9 };
    piece->UpdateExtent(extent);
    observed.ExpectNone("voxel limit: a 10 x 10 x 10 sub-extent");
    Check(piece->GetOutput()->GetNumberOfPoints() == 1000, "voxel limit: sub-extent read");
  }

  // The same reader recovers: error first, then a good read, then an error again (no stale data).
  vtkNew<vtkPTVOpenVDBReader> reader;
  Observed observed;
  observed.Attach(reader);
  reader->SetFileName(missing.c_str());
  reader->Update();
  observed.Expect("reuse: missing file", { missing });
  reader->SetFileName(good.c_str());
  reader->Update();
  observed.ExpectNone("reuse: good file");
  Check(reader->GetOutput()->GetNumberOfPoints() == 32 * 32 * 32,
    "reuse: the good file must be read after an error");
  reader->SetFileName(truncated.c_str());
  reader->Update();
  observed.Expect("reuse: truncated file", { truncated });
  Check(reader->GetOutput()->GetNumberOfPoints() == 0,
    "reuse: a failed read must not leave the previous data in the output");
}

void WriterErrors(const std::string& dir)
{
  ExpectWriteError("no input", nullptr, dir + "/ptv_errors_w_noinput.vdb", { "input" });

  auto noScalars = vtkSmartPointer<vtkImageData>::New();
  noScalars->SetDimensions(3, 3, 3);
  ExpectWriteError(
    "no scalars", noScalars, dir + "/ptv_errors_w_noscalars.vdb", { "no point-data scalars" });

  ExpectWriteError("short scalars", MakeImage(1, VTK_SHORT), dir + "/ptv_errors_w_short.vdb",
    { "short", "vtkImageCast" });

  ExpectWriteError("3 components", MakeImage(3, VTK_FLOAT), dir + "/ptv_errors_w_vector.vdb",
    { "3 components" });

  auto named = MakeImage(1, VTK_FLOAT);
  {
    vtkNew<vtkPTVOpenVDBWriter> writer;
    Observed observed;
    observed.Attach(writer);
    writer->SetInputData(named);
    writer->SetArrayName("nosucharray");
    const std::string file = dir + "/ptv_errors_w_noarray.vdb";
    writer->SetFileName(file.c_str());
    Check(writer->Write() == 0, "unknown ArrayName: Write() must return 0");
    observed.Expect("unknown ArrayName", { "'nosucharray'" });
    Check(!vtksys::SystemTools::FileExists(file), "unknown ArrayName: no file may be created");
  }

  auto nonUniform = MakeImage(1, VTK_FLOAT);
  nonUniform->SetSpacing(0.5, 0.25, 0.5);
  ExpectWriteError("non-uniform spacing", nonUniform, dir + "/ptv_errors_w_spacing.vdb",
    { "non-uniform", "0.25" });

  auto rotated = MakeImage(1, VTK_FLOAT);
  rotated->SetDirectionMatrix(0, -1, 0, 1, 0, 0, 0, 0, 1);
  ExpectWriteError("rotated image", rotated, dir + "/ptv_errors_w_rotated.vdb", { "direction" });

  const std::string unwritable = "/proc/ptv-no/x.vdb";
  ExpectWriteError(
    "unwritable folder", MakeImage(1, VTK_FLOAT), unwritable, { unwritable, "No such file" });
  Check(!vtksys::SystemTools::FileExists(unwritable + ".tmp-" + std::to_string(getpid())),
    "unwritable folder: no temporary file may remain");

  // The writer works after errors.
  vtkNew<vtkPTVOpenVDBWriter> writer;
  Observed observed;
  observed.Attach(writer);
  writer->SetInputData(MakeImage(1, VTK_SHORT));
  writer->SetFileName((dir + "/ptv_errors_w_reuse.vdb").c_str());
  Check(writer->Write() == 0, "reuse: short input must fail");
  observed.Expect("reuse: short input", { "short" });
  writer->SetInputData(MakeImage(1, VTK_FLOAT));
  Check(writer->Write() == 1, "reuse: float input must be written after an error");
  observed.ExpectNone("reuse: float input");
  Check(vtksys::SystemTools::FileExists(dir + "/ptv_errors_w_reuse.vdb"),
    "reuse: the file must exist");
}

} // anonymous namespace

int TestPTVOpenVDBReaderErrors(int argc, char* argv[])
{
  const std::string dir = TempDir(argc, argv);
  ReaderErrors(dir);
  WriterErrors(dir);
  if (failures)
  {
    std::cerr << failures << " check(s) failed\n";
    return EXIT_FAILURE;
  }
  std::cout << "TestPTVOpenVDBReaderErrors passed\n";
  return EXIT_SUCCESS;
}
