// floorcast: simulation and benchmarking test-bed for floor-plan-based indoor localization.
#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>

#include "cli_common.hpp"
#include "floorcast/core/types.hpp"

int main(int argc, char** argv) {
  CLI::App app{"floorcast: floor-plan-based indoor localization test-bed (PALMS / PALMS+ family)"};
  app.set_version_flag("--version", std::string("floorcast ") + FLOORCAST_VERSION);
  app.require_subcommand(1);
  floorcast::cli::register_all(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {  // --help, --version
    return app.exit(e);
  } catch (const CLI::ParseError& e) {  // a usage error: one exit code (README, "Exit codes")
    (void)app.exit(e);
    return floorcast::cli::kExitUsage;
  } catch (const floorcast::cli::CommandExit& e) {
    return e.code;
  } catch (const floorcast::InputError& e) {
    std::cerr << "floorcast: error: " << e.what() << "\n";
    return floorcast::cli::kExitUsage;
  } catch (const std::exception& e) {
    std::cerr << "floorcast: internal error: " << e.what() << "\n";
    return floorcast::cli::kExitInternal;
  }
  return 0;
}
