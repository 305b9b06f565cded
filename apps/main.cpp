// The navaid command-line program.
#include <CLI/CLI.hpp>

int main(int argc, char** argv) {
  CLI::App app{"navaid: navigation aids for blind and low-vision people"};
  app.require_subcommand(1);
  CLI11_PARSE(app, argc, argv);
  return 0;
}
