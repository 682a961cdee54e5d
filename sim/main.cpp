// hotend-sim: runs the real firmware images in simavr against simulated hotends (see cli.cpp).
#include "sim/cli.h"

int main(int argc, char** argv) { return sim::cli_main(argc, argv); }
