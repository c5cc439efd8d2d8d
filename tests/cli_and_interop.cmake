# Included by tests/CMakeLists.txt: the CLI tests and the third-party Modbus peers (run by the
# plain builds and by the coverage build).
# --- the CLI -------------------------------------------------------------------------------
if(TARGET motionbus_cli)
  file(GLOB MOTIONBUS_CLI_TEST_SOURCES CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/cli/*.cpp")
  find_package(Threads REQUIRED)
  add_executable(motionbus_cli_tests main.cpp ${MOTIONBUS_CLI_TEST_SOURCES})
  target_link_libraries(motionbus_cli_tests PRIVATE motionbus::motionbus motionbus_doctest
    Threads::Threads)
  target_compile_definitions(motionbus_cli_tests PRIVATE
    "MOTIONBUS_CLI_PATH=\"$<TARGET_FILE:motionbus_cli>\"")
  motionbus_project_target(motionbus_cli_tests)
  add_test(NAME cli COMMAND motionbus_cli_tests --no-version)
  # 13 s as a rule; each CLI run is bounded at 30 s (tests/cli/run_cli.hpp), so that a hung run
  # fails its check, named, before the suite's own limit
  set_tests_properties(cli PROPERTIES LABELS "cli" TIMEOUT 300)
  # The bus monitors on a tapped line of pseudo-terminals (tests/cli/monitor_checks.py): timed,
  # so run alone.
  foreach(protocol modbus tformat)
    add_test(NAME cli.monitor.${protocol}
      COMMAND /usr/bin/python3 "${CMAKE_CURRENT_SOURCE_DIR}/cli/monitor_checks.py"
              "$<TARGET_FILE:motionbus_cli>" ${protocol})
    set_tests_properties(cli.monitor.${protocol} PROPERTIES LABELS "cli" TIMEOUT 120
      RUN_SERIAL TRUE)
  endforeach()
  # serve modbus executes broadcasts (FC06, FC10 to unit 0) on an RTU line, a pty: never
  # answered, read back from each unit (tests/cli/serve_broadcast_checks.py): timed, alone.
  add_test(NAME cli.serve.broadcast
    COMMAND /usr/bin/python3 "${CMAKE_CURRENT_SOURCE_DIR}/cli/serve_broadcast_checks.py"
            "$<TARGET_FILE:motionbus_cli>")
  set_tests_properties(cli.serve.broadcast PROPERTIES LABELS "cli" TIMEOUT 60 RUN_SERIAL TRUE)
  # monitor modbus --ascii on a pty pair (tests/cli/monitor_ascii_checks.py): timed, alone.
  add_test(NAME cli.monitor.ascii
    COMMAND /usr/bin/python3 "${CMAKE_CURRENT_SOURCE_DIR}/cli/monitor_ascii_checks.py"
            "$<TARGET_FILE:motionbus_cli>")
  set_tests_properties(cli.monitor.ascii PROPERTIES LABELS "cli" TIMEOUT 60 RUN_SERIAL TRUE)
  # The sample recordings shipped in examples/captures/, decoded to the frames they hold.
  add_test(NAME cli.sample_captures
    COMMAND /usr/bin/python3 "${CMAKE_CURRENT_SOURCE_DIR}/cli/sample_captures_check.py"
            "$<TARGET_FILE:motionbus_cli>" "${PROJECT_SOURCE_DIR}")
  set_tests_properties(cli.sample_captures PROPERTIES LABELS "cli" TIMEOUT 120)
  # Every error name the CLI can print is in docs/cli.md (and the docs name no other).
  add_test(NAME cli.error_names
    COMMAND /usr/bin/python3 "${CMAKE_CURRENT_SOURCE_DIR}/cli/error_names_check.py"
            "${PROJECT_SOURCE_DIR}")
  set_tests_properties(cli.error_names PROPERTIES LABELS "cli" TIMEOUT 60)
  # Recordings made by the real tools (Icarus Verilog, sigrok-cli) and encode --vcd, decoded
  # (tests/captures/capture_checks.py).
  find_program(MOTIONBUS_IVERILOG iverilog)
  find_program(MOTIONBUS_VVP vvp)
  find_program(MOTIONBUS_SIGROK_CLI sigrok-cli)
  if(MOTIONBUS_IVERILOG AND MOTIONBUS_VVP AND MOTIONBUS_SIGROK_CLI)
    add_test(NAME cli.captures
      COMMAND /usr/bin/python3 "${CMAKE_CURRENT_SOURCE_DIR}/captures/capture_checks.py"
              "$<TARGET_FILE:motionbus_cli>" "${CMAKE_CURRENT_SOURCE_DIR}/captures"
              "${CMAKE_CURRENT_BINARY_DIR}/captures")
    set_tests_properties(cli.captures PROPERTIES LABELS "cli" TIMEOUT 120)
  elseif(MOTIONBUS_REQUIRE_ALL_CHECKS)
    message(FATAL_ERROR "the capture tests need iverilog and sigrok-cli")
  endif()
endif()

# --- interoperability: third-party Modbus masters against the SM unit emulator ------------
if(TARGET motionbus_cli)
  find_package(PkgConfig QUIET)
  if(PKG_CONFIG_FOUND)
    pkg_check_modules(MOTIONBUS_LIBMODBUS QUIET libmodbus)
  endif()
  find_program(MOTIONBUS_SOCAT socat)
  set(MOTIONBUS_DEBIAN_PYTHON /usr/bin/python3)
  set(pymodbus_ok FALSE)
  if(EXISTS "${MOTIONBUS_DEBIAN_PYTHON}")
    execute_process(COMMAND "${MOTIONBUS_DEBIAN_PYTHON}" -c "import pymodbus, serial, serial_asyncio"
      RESULT_VARIABLE pymodbus_rc OUTPUT_QUIET ERROR_QUIET)
    if(pymodbus_rc EQUAL 0)
      set(pymodbus_ok TRUE)
    endif()
  endif()
  if(MOTIONBUS_LIBMODBUS_FOUND AND MOTIONBUS_SOCAT AND pymodbus_ok)
    enable_language(C)
    foreach(peer client server)
      add_executable(motionbus_libmodbus_${peer} interop/libmodbus_${peer}.c)
      target_include_directories(motionbus_libmodbus_${peer} SYSTEM PRIVATE
        ${MOTIONBUS_LIBMODBUS_INCLUDE_DIRS})
      target_include_directories(motionbus_libmodbus_${peer} PRIVATE
        "${CMAKE_CURRENT_SOURCE_DIR}/support")
      target_link_libraries(motionbus_libmodbus_${peer} PRIVATE ${MOTIONBUS_LIBMODBUS_LINK_LIBRARIES})
      target_compile_options(motionbus_libmodbus_${peer} PRIVATE -Wall -Wextra -Werror)
    endforeach()
    add_test(NAME interop.sm_unit
      COMMAND bash "${CMAKE_CURRENT_SOURCE_DIR}/interop/run_interop.sh"
              "$<TARGET_FILE:motionbus_cli>" "$<TARGET_FILE:motionbus_libmodbus_client>")
    set_tests_properties(interop.sm_unit PROPERTIES LABELS "interop" TIMEOUT 120)
    add_test(NAME interop.client
      COMMAND bash "${CMAKE_CURRENT_SOURCE_DIR}/interop/run_client_interop.sh"
              "$<TARGET_FILE:motionbus_cli>" "$<TARGET_FILE:motionbus_libmodbus_server>")
    set_tests_properties(interop.client PROPERTIES LABELS "interop" TIMEOUT 180)
    # libmodbus's and pymodbus's TCP clients through `motionbus gateway` to the SM unit
    # emulator (tests/interop/run_gateway_interop.sh): timed (0B, the idle timeout), so alone.
    add_executable(motionbus_libmodbus_tcp_client interop/libmodbus_tcp_client.c)
    target_include_directories(motionbus_libmodbus_tcp_client SYSTEM PRIVATE
      ${MOTIONBUS_LIBMODBUS_INCLUDE_DIRS})
    target_include_directories(motionbus_libmodbus_tcp_client PRIVATE
      "${CMAKE_CURRENT_SOURCE_DIR}/support")
    target_link_libraries(motionbus_libmodbus_tcp_client PRIVATE
      ${MOTIONBUS_LIBMODBUS_LINK_LIBRARIES})
    target_compile_options(motionbus_libmodbus_tcp_client PRIVATE -Wall -Wextra -Werror
      -Wno-unused-function)  # libmodbus_peer.h's serial open_master
    add_test(NAME interop.gateway
      COMMAND bash "${CMAKE_CURRENT_SOURCE_DIR}/interop/run_gateway_interop.sh"
              "$<TARGET_FILE:motionbus_cli>" "$<TARGET_FILE:motionbus_libmodbus_tcp_client>")
    set_tests_properties(interop.gateway PROPERTIES LABELS "interop" TIMEOUT 180
      RUN_SERIAL TRUE)
    # read modbus --ascii against pymodbus's ASCII server (tests/interop/run_ascii_interop.sh)
    add_test(NAME interop.ascii
      COMMAND bash "${CMAKE_CURRENT_SOURCE_DIR}/interop/run_ascii_interop.sh"
              "$<TARGET_FILE:motionbus_cli>")
    set_tests_properties(interop.ascii PROPERTIES LABELS "interop" TIMEOUT 120)
  elseif(MOTIONBUS_REQUIRE_ALL_CHECKS)
    message(FATAL_ERROR "interop tests need libmodbus-dev, socat, python3-pymodbus, python3-serial and python3-serial-asyncio")
  endif()
endif()


# --- pymodbus's ASCII and RTU framers against motionbus's ASCII framer and RTU over TCP ------
# (offline: frames built and parsed both ways, tests/interop/pymodbus_framers.py)
if(EXISTS /usr/bin/python3)
  execute_process(COMMAND /usr/bin/python3 -c "import pymodbus.framer.ascii_framer"
    RESULT_VARIABLE pymodbus_framers_rc OUTPUT_QUIET ERROR_QUIET)
endif()
if(pymodbus_framers_rc EQUAL 0)
  add_executable(motionbus_interop_framers interop/framers_tool.cpp)
  target_link_libraries(motionbus_interop_framers PRIVATE motionbus::motionbus)
  motionbus_project_target(motionbus_interop_framers)
  add_test(NAME interop.pymodbus_framers
    COMMAND /usr/bin/python3 "${CMAKE_CURRENT_SOURCE_DIR}/interop/pymodbus_framers.py"
            "$<TARGET_FILE:motionbus_interop_framers>")
  set_tests_properties(interop.pymodbus_framers PROPERTIES LABELS "interop" TIMEOUT 120)
  # the same RTU framer against pymodbus's on random streams (valid frames, noise, bit flips,
  # cut frames) from a fixed seed, server and client roles; the classes of difference in
  # docs/modbus.md §14 (tests/interop/pymodbus_framer_differential.py)
  add_test(NAME interop.pymodbus_framer_differential
    COMMAND /usr/bin/python3
            "${CMAKE_CURRENT_SOURCE_DIR}/interop/pymodbus_framer_differential.py"
            "$<TARGET_FILE:motionbus_interop_framers>" --seed 28 --frames 3000 --exchanges 1500
            --docs "${PROJECT_SOURCE_DIR}/docs/modbus.md")
  set_tests_properties(interop.pymodbus_framer_differential PROPERTIES LABELS "interop"
    TIMEOUT 120)
elseif(MOTIONBUS_REQUIRE_ALL_CHECKS)
  message(FATAL_ERROR "the pymodbus framer interop test needs python3-pymodbus")
endif()
# --- typed values (modbus/values.hpp) against pymodbus's BinaryPayloadBuilder/Decoder and
# libmodbus's value helpers (tests/interop/values_check.py) -----------------------------------
find_package(PkgConfig QUIET)
if(PKG_CONFIG_FOUND)
  pkg_check_modules(MOTIONBUS_LIBMODBUS_VALUES QUIET libmodbus)
endif()
set(values_pymodbus_ok FALSE)
if(EXISTS /usr/bin/python3)
  execute_process(COMMAND /usr/bin/python3 -c "import pymodbus.payload"
    RESULT_VARIABLE values_pymodbus_rc OUTPUT_QUIET ERROR_QUIET)
  if(values_pymodbus_rc EQUAL 0)
    set(values_pymodbus_ok TRUE)
  endif()
endif()
if(MOTIONBUS_LIBMODBUS_VALUES_FOUND AND values_pymodbus_ok)
  enable_language(C)
  add_executable(motionbus_values_dump interop/values_dump.cpp)
  target_link_libraries(motionbus_values_dump PRIVATE motionbus::motionbus)
  motionbus_project_target(motionbus_values_dump)
  add_executable(motionbus_libmodbus_values interop/libmodbus_values.c)
  target_include_directories(motionbus_libmodbus_values SYSTEM PRIVATE
    ${MOTIONBUS_LIBMODBUS_VALUES_INCLUDE_DIRS})
  target_link_libraries(motionbus_libmodbus_values PRIVATE
    ${MOTIONBUS_LIBMODBUS_VALUES_LINK_LIBRARIES})
  target_compile_options(motionbus_libmodbus_values PRIVATE -Wall -Wextra -Werror)
  add_test(NAME interop.values
    COMMAND /usr/bin/python3 "${CMAKE_CURRENT_SOURCE_DIR}/interop/values_check.py"
            "$<TARGET_FILE:motionbus_values_dump>" "$<TARGET_FILE:motionbus_libmodbus_values>")
  set_tests_properties(interop.values PROPERTIES LABELS "interop" TIMEOUT 120)
elseif(MOTIONBUS_REQUIRE_ALL_CHECKS)
  message(FATAL_ERROR "the typed-value interop test needs libmodbus-dev and python3-pymodbus")
endif()
# The server against libmodbus's modbus_reply, same image and requests, 20000 random requests
# from a fixed seed; differences only of the classes docs/modbus.md lists
# (tests/interop/server_differential.cpp)
if(MOTIONBUS_LIBMODBUS_VALUES_FOUND)
  add_executable(motionbus_server_differential interop/server_differential.cpp)
  target_include_directories(motionbus_server_differential SYSTEM PRIVATE
    ${MOTIONBUS_LIBMODBUS_VALUES_INCLUDE_DIRS})
  target_include_directories(motionbus_server_differential PRIVATE
    "${CMAKE_CURRENT_SOURCE_DIR}/support")
  target_link_libraries(motionbus_server_differential PRIVATE motionbus::motionbus
    ${MOTIONBUS_LIBMODBUS_VALUES_LINK_LIBRARIES})
  motionbus_project_target(motionbus_server_differential)
  add_test(NAME interop.server_differential COMMAND motionbus_server_differential 20000)
  set_tests_properties(interop.server_differential PROPERTIES LABELS "interop" TIMEOUT 120)
  # The client's response checks against libmodbus's (check_confirmation, through its master's
  # calls), 20000 random requests and mostly mutated responses from a fixed seed
  # (tests/interop/client_differential.cpp)
  add_executable(motionbus_client_differential interop/client_differential.cpp)
  target_include_directories(motionbus_client_differential SYSTEM PRIVATE
    ${MOTIONBUS_LIBMODBUS_VALUES_INCLUDE_DIRS})
  target_link_libraries(motionbus_client_differential PRIVATE motionbus::motionbus
    ${MOTIONBUS_LIBMODBUS_VALUES_LINK_LIBRARIES})
  motionbus_project_target(motionbus_client_differential)
  add_test(NAME interop.client_differential
    COMMAND motionbus_client_differential 20000 0x28C11E)
  set_tests_properties(interop.client_differential PROPERTIES LABELS "interop" TIMEOUT 120)
elseif(MOTIONBUS_REQUIRE_ALL_CHECKS)
  message(FATAL_ERROR "the server and client differential tests need libmodbus-dev")
endif()
# FC14/15 file records against pymodbus's file_message classes (tests/interop/file_record_check.py)
if(values_pymodbus_ok)
  add_executable(motionbus_file_record_peer interop/file_record_peer.cpp)
  target_link_libraries(motionbus_file_record_peer PRIVATE motionbus::motionbus)
  motionbus_project_target(motionbus_file_record_peer)
  add_test(NAME interop.file_records
    COMMAND /usr/bin/python3 "${CMAKE_CURRENT_SOURCE_DIR}/interop/file_record_check.py"
            "$<TARGET_FILE:motionbus_file_record_peer>")
  set_tests_properties(interop.file_records PROPERTIES LABELS "interop" TIMEOUT 120)
elseif(MOTIONBUS_REQUIRE_ALL_CHECKS)
  message(FATAL_ERROR "the file-record interop test needs python3-pymodbus")
endif()
# --- the Python package (python/, docs/python.md) ------------------------------------------
# python_pytest: the suite against the build tree's package; python_install: the documented
# pip install from a pristine copy into a fresh directory, then the suite against that.
if(TARGET motionbus_python AND NOT TEST python_pytest)
  add_test(NAME python_pytest
    COMMAND ${CMAKE_COMMAND} -E env
            "PYTHONPATH=${PROJECT_BINARY_DIR}/python:${CMAKE_CURRENT_SOURCE_DIR}/python"
            /usr/bin/python3 -m pytest -q -p no:cacheprovider "${CMAKE_CURRENT_SOURCE_DIR}/python")
  set_tests_properties(python_pytest PROPERTIES LABELS "python" TIMEOUT 300)
  add_test(NAME python_install
    COMMAND /usr/bin/python3 "${CMAKE_CURRENT_SOURCE_DIR}/python/install_and_test.py"
            "${PROJECT_SOURCE_DIR}" "${PROJECT_BINARY_DIR}/python-install")
  set_tests_properties(python_install PROPERTIES LABELS "python" TIMEOUT 900)
endif()
# --- the sigrok decoders (sigrok/decoders, docs/sigrok.md) ----------------------------------
# sigrok_decoders: sigrok-cli runs tformat (on uart) and biss over captures the tests build
# from the package's encoders (tests/sigrok), against the build tree's package.
if(TARGET motionbus_python AND NOT TEST sigrok_decoders)
  find_program(MOTIONBUS_SIGROK_CLI sigrok-cli)
  if(MOTIONBUS_SIGROK_CLI)
    add_test(NAME sigrok_decoders
      COMMAND ${CMAKE_COMMAND} -E env
              "PYTHONPATH=${PROJECT_BINARY_DIR}/python:${CMAKE_CURRENT_SOURCE_DIR}/sigrok"
              "SIGROK_CLI=${MOTIONBUS_SIGROK_CLI}"
              /usr/bin/python3 -m pytest -q -p no:cacheprovider "${CMAKE_CURRENT_SOURCE_DIR}/sigrok")
    set_tests_properties(sigrok_decoders PROPERTIES LABELS "sigrok;python" TIMEOUT 300)
  elseif(MOTIONBUS_REQUIRE_ALL_CHECKS)
    message(FATAL_ERROR "the sigrok decoder tests need sigrok-cli")
  endif()
endif()
