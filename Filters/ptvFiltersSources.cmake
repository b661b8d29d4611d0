# The sources of PTV::Filters, in one place: Filters/CMakeLists.txt builds the module from them
# and Testing/Fuzz/CMakeLists.txt compiles them again with the fuzzing instrumentation.
# Validators/: the file-format checks that run before OpenVDB and OpenEXR read a file, each to
# be retired when the library it guards is fixed (Validators/README.md).
set(ptv_filters_classes
  vtkPTVOpenVDBReader
  vtkPTVOpenVDBWriter
  vtkPTVEXRPassReader
  vtkPTVEXRPassWriter)
set(ptv_filters_private_headers
  ptvAtomicWrite.h
  Validators/ptvBoundedReader.h
  ptvEXRChannels.h
  Validators/ptvEXRLayout.h
  ptvOpenVDBGrid.h
  ptvOpenVDBGuard.h
  Validators/ptvOpenVDBLayout.h
  Validators/ptvOpenVDBTree.h
  ptvQuote.h)
set(ptv_filters_sources
  ptvAtomicWrite.cxx
  ptvEXRChannels.cxx
  Validators/ptvEXRLayout.cxx
  ptvOpenVDBGrid.cxx
  ptvOpenVDBWrite.cxx
  Validators/ptvOpenVDBLayout.cxx
  Validators/ptvOpenVDBTree.cxx)
