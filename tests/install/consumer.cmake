# Run by CTest as `cmake -P` (tests/install/CMakeLists.txt): install, build
# examples/consumer against the prefix, run it; then a program compiled and linked with
# pkg-config's flags alone. Fails with the step's output on the first error.
function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}\n${err}")
  endif()
  set(run_output "${out}" PARENT_SCOPE)
endfunction()

function(expect text regex)
  if(NOT text MATCHES "${regex}")
    message(FATAL_ERROR "expected /${regex}/ in:\n${text}")
  endif()
endfunction()

set(prefix ${WORK_DIR}/prefix)
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})

run("cmake --install" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
foreach(f bin/dmbd include/dmbd/blocks/transfer_function.hpp lib/libdmbd_sim.a lib/libdmbd_scenario.a lib/cmake/dmbd/dmbdConfig.cmake
          lib/pkgconfig/dmbd.pc share/dmbd/robots/draco/draco.urdf share/dmbd/robots/draco/actuators.yaml share/dmbd/robots/draco/robot.yaml)
  if(NOT EXISTS ${prefix}/${f})
    message(FATAL_ERROR "not installed: ${f}")
  endif()
endforeach()

# find_package(dmbd): the consumer example, with the robot files from the prefix.
run("configure examples/consumer" ${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples/consumer -B ${WORK_DIR}/consumer
    -G ${GENERATOR} -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_PREFIX_PATH=${prefix})
run("build examples/consumer" ${CMAKE_COMMAND} --build ${WORK_DIR}/consumer)
run("run the consumer" ${CMAKE_COMMAND} -E env DMBD_ROBOT_PATH=${prefix}/share/dmbd/robots
    ${WORK_DIR}/consumer/consumer ${SOURCE_DIR}/examples/diagrams/force_dob.yaml F_d F)
# (20 + 2s) / (s (s + 4)) closed: s² + 6s + 20, poles −3 ± j√11.
expect("${run_output}" "closed-loop pole -3\\.000000 \\+3\\.316625j")
expect("${run_output}" "closed-loop pole -3\\.000000 -3\\.316625j")
expect("${run_output}" "F_d -> F: order [1-9][0-9]*, dc gain 1(\\.0*[0-9]*)?\n")
expect("${run_output}" "DRACO: 3[5-9]\\.[0-9]+ kg")

# pkg-config alone: flags for a program that uses blocks and diagrams.
run("pkg-config" ${CMAKE_COMMAND} -E env PKG_CONFIG_PATH=${prefix}/lib/pkgconfig ${PKG_CONFIG} --cflags --libs dmbd)
separate_arguments(flags UNIX_COMMAND "${run_output}")
file(WRITE ${WORK_DIR}/pc.cpp [=[
#include <cstdio>
#include "dmbd/blocks/transfer_function.hpp"
#include "dmbd/diagrams/diagram.hpp"
int main(int argc, char** argv) {
  const auto d = dmbd::diagrams::Diagram::load(argv[argc - 1]);
  const auto p = dmbd::blocks::TransferFunction::parse("1/((s+1)*(s+2))").poles();
  std::printf("poles %.1f %.1f\n", p[0].real() + p[1].real(), p[0].real() * p[1].real());
  return d ? 0 : 1;
}
]=])
run("compile with pkg-config's flags" ${CXX} -O1 -o ${WORK_DIR}/pc ${WORK_DIR}/pc.cpp ${flags})
run("run the pkg-config program" ${WORK_DIR}/pc ${SOURCE_DIR}/examples/diagrams/force_dob.yaml)
expect("${run_output}" "poles -3\\.0 2\\.0")
