#include <CLI/CLI.hpp>

int main(int argc, char** argv) {
  CLI::App app{"rubcont: continuation and bifurcation for rotor–stator rub"};
  app.require_subcommand(1);
  app.add_subcommand("run", "run everything the scene asks for");
  CLI11_PARSE(app, argc, argv);
  return 0;
}
