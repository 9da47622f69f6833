# Prints the size report of a firmware image after it links: text / data / bss as arm-none-eabi-size sees
# them, flash use (text + data) and static SRAM use (data + bss) against the image's budgets. Informative
# only: tests/firmware turns the budgets into pass/fail (with the measured stack added to SRAM).
execute_process(COMMAND ${SIZE} -B ${ELF} OUTPUT_VARIABLE out RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${SIZE} failed on ${ELF}")
endif()
string(REGEX MATCH "\n[ \t]*([0-9]+)[ \t]+([0-9]+)[ \t]+([0-9]+)" m "${out}")
if(NOT m)
  message(FATAL_ERROR "could not parse: ${out}")
endif()
set(text ${CMAKE_MATCH_1})
set(data ${CMAKE_MATCH_2})
set(bss ${CMAKE_MATCH_3})
math(EXPR flash "${text} + ${data}")
math(EXPR sram "${data} + ${bss}")
math(EXPR flash_pct "100 * ${flash} / ${FLASH_BUDGET}")
math(EXPR sram_pct "100 * ${sram} / ${SRAM_BUDGET}")
message("size ${IMAGE}: text ${text}  data ${data}  bss ${bss}  |  flash ${flash} / ${FLASH_BUDGET} B (${flash_pct} %)"
        "  |  SRAM static ${sram} / ${SRAM_BUDGET} B (${sram_pct} %) + stack (reserved ${STACK_RESERVED} B)")
