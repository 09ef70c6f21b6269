// cli/repl.cpp — `fortu repl`: placeholder until its issue lands; refuses clearly.
#include "cli/commands.hpp"

#include <iostream>

namespace fortu {

int run_repl_command(const std::vector<std::string>&) {
    std::cerr << "fortu: error: 'fortu repl' is not available in this build yet\n";
    return 2;
}

}  // namespace fortu
