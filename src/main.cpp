#include "app/cli.hpp"

int main(int argc, char** argv)
{
    return pr::run_cli(argc, argv);
}
