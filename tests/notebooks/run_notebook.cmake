# cmake -DPYTHON=<python3> -DNOTEBOOK=<file.ipynb> -DOUTPUT_DIR=<dir> [-DCELL_TIMEOUT=60]
#       -P run_notebook.cmake
# Executes NOTEBOOK top to bottom with nbconvert into OUTPUT_DIR and fails (exit 1) when
#   - the stored notebook has outputs (notebooks are kept clean: CI produces every figure and
#     number when it runs them),
#   - a cell raises (nbconvert's exit status; the notebooks assert every number their text states),
#   - the executed notebook has an error output or fewer PNG figures than its source has
#     plt.show() calls.
foreach(var PYTHON NOTEBOOK OUTPUT_DIR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "run_notebook.cmake: -D${var}=... is required")
  endif()
endforeach()
if(NOT DEFINED CELL_TIMEOUT)
  set(CELL_TIMEOUT 60)
endif()

file(READ ${NOTEBOOK} source)
if(source MATCHES "\"output_type\"" OR source MATCHES "\"execution_count\": [0-9]")
  message(FATAL_ERROR "${NOTEBOOK} is stored with outputs; clear them (Jupyter: Kernel > Restart & "
                      "Clear Output, or jupyter nbconvert --clear-output --inplace ${NOTEBOOK})")
endif()
string(REGEX MATCHALL "plt\\.show\\(\\)" shows "${source}")
list(LENGTH shows expected_figures)

get_filename_component(name ${NOTEBOOK} NAME)
file(MAKE_DIRECTORY ${OUTPUT_DIR})
file(REMOVE ${OUTPUT_DIR}/${name})
execute_process(
  COMMAND ${PYTHON} -m nbconvert --to notebook --execute
          --ExecutePreprocessor.timeout=${CELL_TIMEOUT}
          --ExecutePreprocessor.kernel_name=python3
          "--ExecutePreprocessor.extra_arguments=[\"--colors=NoColor\"]"
          --output-dir ${OUTPUT_DIR} ${NOTEBOOK}
  RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "${name}: a cell failed (nbconvert exit status ${status}); the traceback is "
                      "above")
endif()

file(READ ${OUTPUT_DIR}/${name} executed)
if(executed MATCHES "\"output_type\": \"error\"")
  message(FATAL_ERROR "${name}: an error output in ${OUTPUT_DIR}/${name}")
endif()
string(REGEX MATCHALL "\"image/png\"" figures "${executed}")
list(LENGTH figures drawn)
if(drawn LESS expected_figures)
  message(FATAL_ERROR "${name}: ${drawn} figures drawn, expected at least ${expected_figures} "
                      "(one per plt.show())")
endif()
message(STATUS "${name}: ran top to bottom, ${drawn} figures, executed copy in "
               "${OUTPUT_DIR}/${name}")
