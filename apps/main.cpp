// floorcast: simulation and benchmarking test-bed for floor-plan-based indoor localization.
#include "cli_common.hpp"

int main(int argc, char** argv) { return floorcast::cli::run_cli(argc, argv); }
