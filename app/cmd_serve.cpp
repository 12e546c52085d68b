// foldcast serve DIR: the .fca files under DIR and the browser player over HTTP, until
// Ctrl-C (docs/player.md).
#include <cstdio>

#include "commands.hpp"
#include "foldcast/serve/serve.hpp"

namespace foldcast::app {

Command serve_command(CLI::App& app) {
    auto* sub =
        app.add_subcommand("serve", "Serve the .fca files under DIR and the browser player over HTTP (until Ctrl-C)");
    struct Opts {
        std::string dir, bind = "127.0.0.1", web_dir = FOLDCAST_WEB_DIR;
        int port = 8080;
        double throttle_kbps = 0.0;
        bool log = false;
    };
    auto o = std::make_shared<Opts>();
    sub->add_option("dir", o->dir, "folder whose .fca files (and sub-folders') are served")->required();
    sub->add_option("--port", o->port, "TCP port, 0 for any free one")->capture_default_str();
    sub->add_option("--bind", o->bind, "address to listen on (127.0.0.1: this machine only)")->capture_default_str();
    sub->add_option("--throttle-kbps", o->throttle_kbps,
                    "simulate a slow link: all .fca downloads share K kilobits per second");
    sub->add_option("--web-dir", o->web_dir, "the built player")->capture_default_str();
    sub->add_flag("--log", o->log, "one line per request on stderr");

    return {sub, [o, sub]() {
                serve::Options options;
                options.root = o->dir;
                options.web_dir = o->web_dir;
                options.bind = o->bind;
                options.port = o->port;
                if (sub->count("--throttle-kbps")) options.throttle_kbps = o->throttle_kbps;
                options.log = o->log;
                serve::Server server(options);
                std::printf("serving %s on http://%s:%d/ (Ctrl-C stops)\n", o->dir.c_str(), o->bind.c_str(),
                            server.port());
                std::fflush(stdout);
                serve::run_until_signal(server);
                return 0;
            }};
}

}  // namespace foldcast::app
