// cli/bench.cpp — `fortu bench`: placeholder until its issue lands; refuses clearly.
#include "cli/commands.hpp"

#include <iostream>

namespace fortu {

int run_bench_command(const std::vector<std::string>&) {
    std::cerr << "fortu: error: 'fortu bench' is not available in this build yet\n";
    return 2;
}

}  // namespace fortu
