// What a window manager and a file manager send a window, for the viewer's key tests
// (tests/cli/view_keys.sh): xdotool sends keys, but has neither the close button nor drag and drop.
//   x11_send close WINDOW
//       the window manager's close (a WM_PROTOCOLS client message, WM_DELETE_WINDOW), as its
//       title bar's close button sends (xdotool's windowclose destroys the window instead)
//   x11_send drop WINDOW FILE
//       drops FILE on the window by the XDND protocol (version 5), as a file manager does: enter
//       with text/uri-list, a position at the window's centre, drop, then hands the file's URI
//       over when the window asks for the selection. Exit 0 once the window says it has finished
//       and took the file, 1 otherwise (10 s at most).
// WINDOW is the decimal id xdotool prints. Only Xlib: no GLFW, nothing of prismrelief.
#include <X11/Xatom.h>
#include <X11/Xlib.h>

#include <sys/select.h>

#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace {

Atom atom(Display* d, const char* name) { return XInternAtom(d, name, False); }

void send_client_message(Display* d, Window to, Atom type, long l0, long l1, long l2, long l3, long l4)
{
    XEvent e{};
    e.xclient.type = ClientMessage;
    e.xclient.window = to;
    e.xclient.message_type = type;
    e.xclient.format = 32;
    e.xclient.data.l[0] = l0;
    e.xclient.data.l[1] = l1;
    e.xclient.data.l[2] = l2;
    e.xclient.data.l[3] = l3;
    e.xclient.data.l[4] = l4;
    XSendEvent(d, to, False, NoEventMask, &e);
    XFlush(d);
}

// file:// URI of an absolute path, with everything but unreserved characters and '/' escaped.
std::string file_uri(const std::string& path)
{
    std::string uri = "file://";
    for (unsigned char c : path) {
        if (std::isalnum(c) || std::strchr("/-._~", c)) {
            uri += char(c);
        } else {
            char buf[4];
            std::snprintf(buf, sizeof buf, "%%%02X", c);
            uri += buf;
        }
    }
    return uri;
}

int drop(Display* d, Window target, const std::string& path)
{
    const Atom selection = atom(d, "XdndSelection"), uri_list = atom(d, "text/uri-list");
    const Atom finished = atom(d, "XdndFinished"), copy = atom(d, "XdndActionCopy");
    const Window source = XCreateSimpleWindow(d, DefaultRootWindow(d), 0, 0, 1, 1, 0, 0, 0);
    XSetSelectionOwner(d, selection, source, CurrentTime);
    if (XGetSelectionOwner(d, selection) != source) {
        std::fprintf(stderr, "x11_send: could not own XdndSelection\n");
        return 1;
    }
    XWindowAttributes wa{};
    XGetWindowAttributes(d, target, &wa);
    int x = 0, y = 0;
    Window child = 0;
    XTranslateCoordinates(d, target, DefaultRootWindow(d), wa.width / 2, wa.height / 2, &x, &y, &child);
    const std::string data = file_uri(path) + "\r\n";

    send_client_message(d, target, atom(d, "XdndEnter"), long(source), 5L << 24, long(uri_list), 0, 0);
    send_client_message(d, target, atom(d, "XdndPosition"), long(source), 0, (long(x) << 16) | long(y),
                        CurrentTime, long(copy));
    send_client_message(d, target, atom(d, "XdndDrop"), long(source), 0, CurrentTime, 0, 0);

    const auto start = std::chrono::steady_clock::now();
    while (std::chrono::steady_clock::now() - start < std::chrono::seconds(10)) {
        if (!XPending(d)) {
            fd_set fds;
            FD_ZERO(&fds);
            FD_SET(ConnectionNumber(d), &fds);
            timeval tv{0, 100000};
            select(ConnectionNumber(d) + 1, &fds, nullptr, nullptr, &tv);
            continue;
        }
        XEvent e;
        XNextEvent(d, &e);
        if (e.type == SelectionRequest) {
            const XSelectionRequestEvent& r = e.xselectionrequest;
            XEvent reply{};
            reply.xselection.type = SelectionNotify;
            reply.xselection.requestor = r.requestor;
            reply.xselection.selection = r.selection;
            reply.xselection.target = r.target;
            reply.xselection.time = r.time;
            reply.xselection.property = None;
            if (r.target == uri_list && r.property != None) {
                XChangeProperty(d, r.requestor, r.property, uri_list, 8, PropModeReplace,
                                reinterpret_cast<const unsigned char*>(data.data()), int(data.size()));
                reply.xselection.property = r.property;
            }
            XSendEvent(d, r.requestor, False, NoEventMask, &reply);
            XFlush(d);
        } else if (e.type == ClientMessage && e.xclient.message_type == finished) {
            // (The protocol's bit 0 says "accepted"; GLFW sends the length of the list it read.)
            if (e.xclient.data.l[1] != 0) return 0;
            std::fprintf(stderr, "x11_send: the window refused the drop\n");
            return 1;
        }
    }
    std::fprintf(stderr, "x11_send: no XdndFinished from the window within 10 s\n");
    return 1;
}

} // namespace

int main(int argc, char** argv)
{
    const std::string what = argc > 1 ? argv[1] : "";
    if (!((what == "close" && argc == 3) || (what == "drop" && argc == 4))) {
        std::fprintf(stderr, "usage: x11_send close WINDOW | drop WINDOW FILE\n");
        return 2;
    }
    Display* d = XOpenDisplay(nullptr);
    if (!d) {
        std::fprintf(stderr, "x11_send: cannot open display\n");
        return 1;
    }
    const Window target = Window(std::strtoul(argv[2], nullptr, 10));
    int rc = 0;
    if (what == "close") {
        send_client_message(d, target, atom(d, "WM_PROTOCOLS"), long(atom(d, "WM_DELETE_WINDOW")), CurrentTime, 0,
                            0, 0);
        XSync(d, False);
    } else {
        rc = drop(d, target, argv[3]);
    }
    XCloseDisplay(d);
    return rc;
}
