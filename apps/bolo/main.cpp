// bolo: the command-line tool. The commands are registered in app.cpp (library bolo_cli), so
// the tests run exactly this command line in-process.

#include <iostream>

#include "bolo/commands.hpp"

int main(int argc, char** argv) { return bolo::cli::run_cli(argc, argv, std::cout, std::cerr); }
