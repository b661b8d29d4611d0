# The sources of PTV::Filters, in one place: Filters/CMakeLists.txt builds the module from them
# and Testing/Fuzz/CMakeLists.txt compiles them again with the fuzzing instrumentation.
set(ptv_filters_classes
  vtkPTVOpenVDBReader
  vtkPTVOpenVDBWriter
  vtkPTVEXRPassReader
  vtkPTVEXRPassWriter)
set(ptv_filters_private_headers
  ptvAtomicWrite.h
  ptvBoundedReader.h
  ptvEXRChannels.h
  ptvEXRLayout.h
  ptvOpenVDBGrid.h
  ptvOpenVDBLayout.h
  ptvOpenVDBTree.h
  ptvQuote.h)
set(ptv_filters_sources
  ptvAtomicWrite.cxx
  ptvEXRChannels.cxx
  ptvEXRLayout.cxx
  ptvOpenVDBGrid.cxx
  ptvOpenVDBLayout.cxx
  ptvOpenVDBTree.cxx)
