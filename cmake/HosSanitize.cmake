# HOS_SANITIZE=address,undefined (any -fsanitize= list): instruments every
# target. Undefined behaviour stops the program (no recovery), so a test that
# meets signed overflow or a misaligned load fails instead of printing a line
# nobody reads. Frame pointers keep the reports' stacks complete.
if(HOS_SANITIZE)
  message(STATUS "hos: sanitizers ${HOS_SANITIZE}")
  add_compile_options(-fsanitize=${HOS_SANITIZE} -fno-omit-frame-pointer -g)
  if(HOS_SANITIZE MATCHES "undefined")
    add_compile_options(-fno-sanitize-recover=undefined)
  endif()
  add_link_options(-fsanitize=${HOS_SANITIZE})
endif()
