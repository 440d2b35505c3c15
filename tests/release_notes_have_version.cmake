# Fails unless the release notes (NOTES) have a section for the project's version (VERSION): a
# heading "## vVERSION (" for a released version, or "## Unreleased" naming it as the next.
file(READ "${NOTES}" notes)
string(FIND "${notes}" "\n## v${VERSION} (" released)
string(FIND "${notes}" "\n## Unreleased (v${VERSION})" next)
if(released EQUAL -1 AND next EQUAL -1)
  message(FATAL_ERROR "${NOTES}: no section '## v${VERSION} (...' nor '## Unreleased (v${VERSION})' for the project's version ${VERSION} (CMakeLists.txt)")
endif()
message(STATUS "${NOTES} has a section for v${VERSION}")
