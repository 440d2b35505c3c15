# Fails unless the example consumer (CONSUMER, a CMakeLists.txt) asks find_package(flagsim X.Y) for a
# version that the installed package accepts. The package's compatibility is SameMinorVersion, so X.Y
# must be the project's major.minor (VERSION): the example is written against this version's API.
file(READ "${CONSUMER}" text)
if(NOT text MATCHES "find_package\\(flagsim ([0-9]+\\.[0-9]+)")
  message(FATAL_ERROR "${CONSUMER}: no 'find_package(flagsim X.Y' line")
endif()
set(asked "${CMAKE_MATCH_1}")
string(REGEX MATCH "^[0-9]+\\.[0-9]+" project_minor "${VERSION}")
if(NOT asked STREQUAL project_minor)
  message(FATAL_ERROR "${CONSUMER}: find_package(flagsim ${asked} ...) but the project is ${VERSION} "
                      "(CMakeLists.txt) and its package accepts only ${project_minor}.x (SameMinorVersion)")
endif()
message(STATUS "${CONSUMER} asks for flagsim ${project_minor}")
