# Scripts/new-filter.sh on a copy of the source tree (Testing/Scripts/TestNewFilterTemplate.sh):
# it must write a skeleton that configures and compiles, and refuse bad requests.
add_test(NAME NewFilterTemplate
  COMMAND bash "${CMAKE_CURRENT_LIST_DIR}/TestNewFilterTemplate.sh" "${PROJECT_SOURCE_DIR}"
          "${PROJECT_BINARY_DIR}" "${PROJECT_BINARY_DIR}/Testing/Temporary/new-filter")
set_tests_properties(NewFilterTemplate PROPERTIES LABELS scripts TIMEOUT 600)
