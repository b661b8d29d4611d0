#[=======================================================================[.rst:
FindONNXRuntime
---------------

Finds the ONNX Runtime C/C++ API: ``onnxruntime_cxx_api.h`` and the shared library
``libonnxruntime.so.1``.

Search order: ``ONNXRuntime_ROOT`` / ``PTV_ONNXRUNTIME_ROOT`` (CMake or environment variables;
``scripts/setup.sh`` fills ``<repo>/.deps/onnxruntime`` with the Debian headers and a
``lib/libonnxruntime.so.1`` link to the pip wheel's library), then the standard prefixes (headers
in ``include/`` or ``include/onnxruntime/``, as Debian's ``libonnxruntime-dev`` installs them).

Result variables:

``ONNXRuntime_FOUND``
``ONNXRuntime_INCLUDE_DIR``  folder holding ``onnxruntime_cxx_api.h``
``ONNXRuntime_LIBRARY``      the library, preferably the ``libonnxruntime.so.1`` (SONAME) file
``ONNXRuntime_API_VERSION``  ``ORT_API_VERSION`` of the headers (21 for ONNX Runtime 1.21)
``ONNXRuntime_VERSION``      the library's version from its real file name (``1.21.1``), else
                             ``1.<api version>`` (the headers only know the minor version)

Imported target ``ONNXRuntime::ONNXRuntime``: ``IMPORTED_LOCATION`` is the library file, the
include folder is an INTERFACE include directory. Link it PRIVATE and keep ORT headers out of
public headers. Because the target is imported with a full path, CMake puts the library's folder
into the build-tree RPATH of whatever links it.

The headers' API version must not be newer than the library's (ORT refuses to hand out an API
table newer than itself at run time).
#]=======================================================================]

set(_ptv_ort_hints)
foreach (_ptv_ort_root IN ITEMS "${ONNXRuntime_ROOT}" "$ENV{ONNXRuntime_ROOT}"
    "${PTV_ONNXRUNTIME_ROOT}" "$ENV{PTV_ONNXRUNTIME_ROOT}")
  if (_ptv_ort_root)
    list(APPEND _ptv_ort_hints "${_ptv_ort_root}")
  endif ()
endforeach ()

find_path(ONNXRuntime_INCLUDE_DIR
  NAMES onnxruntime_cxx_api.h
  HINTS ${_ptv_ort_hints}
  PATH_SUFFIXES include include/onnxruntime include/onnxruntime/core/session onnxruntime
  DOC "Folder holding onnxruntime_cxx_api.h")

# Prefer the SONAME file (libonnxruntime.so.1): that is what the loader looks for at run time.
find_library(ONNXRuntime_LIBRARY
  NAMES libonnxruntime.so.1 onnxruntime
  HINTS ${_ptv_ort_hints}
  PATH_SUFFIXES lib lib64 "lib/${CMAKE_LIBRARY_ARCHITECTURE}"
  DOC "ONNX Runtime shared library (libonnxruntime.so.1)")

if (ONNXRuntime_INCLUDE_DIR AND EXISTS "${ONNXRuntime_INCLUDE_DIR}/onnxruntime_c_api.h")
  file(STRINGS "${ONNXRuntime_INCLUDE_DIR}/onnxruntime_c_api.h" _ptv_ort_api_line
    REGEX "^#define ORT_API_VERSION [0-9]+")
  if (_ptv_ort_api_line MATCHES "ORT_API_VERSION ([0-9]+)")
    set(ONNXRuntime_API_VERSION "${CMAKE_MATCH_1}")
    set(ONNXRuntime_VERSION "1.${CMAKE_MATCH_1}")
  endif ()
endif ()
# The real file name carries the full version (libonnxruntime.so.1.21.1 behind the .so.1 link).
if (ONNXRuntime_LIBRARY)
  get_filename_component(_ptv_ort_real "${ONNXRuntime_LIBRARY}" REALPATH)
  if (_ptv_ort_real MATCHES "libonnxruntime\\.so\\.(1\\.([0-9]+)\\.[0-9]+)$")
    set(ONNXRuntime_LIBRARY_VERSION "${CMAKE_MATCH_1}")
    set(_ptv_ort_lib_minor "${CMAKE_MATCH_2}")
    set(ONNXRuntime_VERSION "${ONNXRuntime_LIBRARY_VERSION}")
  endif ()
endif ()

set(_ptv_ort_reason "")
string(REPLACE ";" ", " _ptv_ort_hints_text "${_ptv_ort_hints}") # no ';' in the reason text
# ORT hands out no API table newer than itself: headers must not be newer than the library.
set(ONNXRuntime_HEADERS_NOT_NEWER_THAN_LIBRARY TRUE)
if (ONNXRuntime_API_VERSION AND _ptv_ort_lib_minor AND
    ONNXRuntime_API_VERSION GREATER _ptv_ort_lib_minor)
  set(ONNXRuntime_HEADERS_NOT_NEWER_THAN_LIBRARY FALSE)
  string(APPEND _ptv_ort_reason
    "the headers (API ${ONNXRuntime_API_VERSION}, ${ONNXRuntime_INCLUDE_DIR}) are newer than "
    "the library (${ONNXRuntime_LIBRARY_VERSION}, ${_ptv_ort_real}). ")
endif ()
if (NOT ONNXRuntime_INCLUDE_DIR)
  string(APPEND _ptv_ort_reason
    "onnxruntime_cxx_api.h not found (looked in: ${_ptv_ort_hints_text} and standard prefixes). ")
endif ()
if (NOT ONNXRuntime_LIBRARY)
  string(APPEND _ptv_ort_reason
    "libonnxruntime.so.1 not found (looked in <root>/lib of: ${_ptv_ort_hints_text} and "
    "the standard prefixes). ")
endif ()
if (_ptv_ort_reason)
  string(APPEND _ptv_ort_reason
    "Run scripts/setup.sh (it fetches the headers and links the pip wheel's library into "
    "<repo>/.deps/onnxruntime) or set PTV_ONNXRUNTIME_ROOT to a prefix with include/ and "
    "lib/libonnxruntime.so.1.")
endif ()

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(ONNXRuntime
  REQUIRED_VARS ONNXRuntime_LIBRARY ONNXRuntime_INCLUDE_DIR
    ONNXRuntime_HEADERS_NOT_NEWER_THAN_LIBRARY
  VERSION_VAR ONNXRuntime_VERSION
  REASON_FAILURE_MESSAGE "${_ptv_ort_reason}")

if (ONNXRuntime_FOUND AND NOT TARGET ONNXRuntime::ONNXRuntime)
  add_library(ONNXRuntime::ONNXRuntime SHARED IMPORTED GLOBAL)
  set_target_properties(ONNXRuntime::ONNXRuntime PROPERTIES
    IMPORTED_LOCATION "${ONNXRuntime_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${ONNXRuntime_INCLUDE_DIR}")
endif ()

mark_as_advanced(ONNXRuntime_INCLUDE_DIR ONNXRuntime_LIBRARY)
unset(_ptv_ort_hints)
unset(_ptv_ort_root)
unset(_ptv_ort_api_line)
unset(_ptv_ort_reason)
unset(_ptv_ort_hints_text)
unset(_ptv_ort_real)
unset(_ptv_ort_lib_minor)
