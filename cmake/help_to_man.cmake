# cmake -DPROGRAM=path -DNAME=name -DSECTION=1 -DOUT=file.1 -P help_to_man.cmake
# A manual page from a program's --help: NAME, then the help text verbatim as DESCRIPTION.
execute_process(COMMAND ${PROGRAM} --help OUTPUT_VARIABLE help RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${PROGRAM} --help: exit ${rc}")
endif()
# CLI11 names the program by the path it was started from: the page names it as installed.
string(REPLACE "${PROGRAM}" "${NAME}" help "${help}")
string(REPLACE "\\" "\\e" help "${help}")
string(REGEX REPLACE "(^|\n)([.'])" "\\1\\\\&\\2" help "${help}")
string(TOUPPER "${NAME}" upper)
file(WRITE ${OUT} ".TH ${upper} ${SECTION} \"\" \"cathbox\" \"Cathbox\"\n.SH NAME\n${NAME} \\- ${SUMMARY}\n.SH DESCRIPTION\n.nf\n${help}.fi\n")
