#include "video_stream.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "foldcast/core/error.hpp"

extern char** environ;

namespace foldcast::batch {

namespace {
std::string lower_extension(const std::filesystem::path& p) {
    std::string ext = p.extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

std::string number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", v);
    return text;
}

// ffmpeg's arguments after the raw input.  x264 and libvpx are given a fixed thread count:
// their output depends on it, and the video must be the same bytes on every machine.
std::vector<std::string> encoder_arguments(VideoCodec codec, const VideoOptions& o, cv::Size size) {
    std::vector<std::string> a;
    // yuv420p needs even sides: pad an odd one with the last row or column's colour.
    std::string filter = "scale=out_color_matrix=bt709:out_range=tv";
    if (size.width % 2 || size.height % 2) filter = "pad=ceil(iw/2)*2:ceil(ih/2)*2," + filter;
    a.insert(a.end(), {"-vf", filter, "-pix_fmt", "yuv420p", "-colorspace", "bt709", "-color_primaries", "bt709",
                       "-color_trc", "bt709", "-color_range", "tv"});
    const int crf = o.crf >= 0 ? o.crf : default_crf(codec);
    if (codec == VideoCodec::h264) {
        a.insert(a.end(), {"-c:v", "libx264", "-preset", o.preset.empty() ? "medium" : o.preset, "-threads", "4"});
        if (o.bitrate_kbps > 0) {
            const std::string rate = std::to_string(o.bitrate_kbps) + "k";
            a.insert(a.end(), {"-b:v", rate, "-maxrate", rate, "-bufsize", std::to_string(2 * o.bitrate_kbps) + "k"});
        } else {
            a.insert(a.end(), {"-crf", std::to_string(crf)});
        }
        a.insert(a.end(), {"-movflags", "+faststart", "-f", "mp4"});
    } else {
        a.insert(a.end(),
                 {"-c:v", "libvpx-vp9", "-deadline", "good", "-cpu-used", "2", "-row-mt", "0", "-threads", "1"});
        if (o.bitrate_kbps > 0)
            a.insert(a.end(), {"-b:v", std::to_string(o.bitrate_kbps) + "k"});
        else
            a.insert(a.end(), {"-crf", std::to_string(crf), "-b:v", "0"});
        a.insert(a.end(), {"-f", "webm"});
    }
    // No encoder version or creation time in the container: the same frames, the same bytes.
    a.insert(a.end(), {"-map_metadata", "-1", "-fflags", "+bitexact", "-flags:v", "+bitexact"});
    return a;
}
}  // namespace

VideoCodec video_codec_for(const std::filesystem::path& video) {
    const std::string ext = lower_extension(video);
    if (ext == ".mp4") return VideoCodec::h264;
    if (ext == ".webm") return VideoCodec::vp9;
    throw InputError("turntable video '" + video.string() + "': must end in .mp4 (H.264) or .webm (VP9)");
}

int default_crf(VideoCodec codec) { return codec == VideoCodec::h264 ? 18 : 31; }

void check_video_options(const VideoOptions& o, const std::filesystem::path& video) {
    const VideoCodec codec = video_codec_for(video);
    const std::string what = "turntable video '" + video.string() + "': ";
    const int most = codec == VideoCodec::h264 ? 51 : 63;
    if (o.crf > most)
        throw InputError(what + "quality (CRF) " + std::to_string(o.crf) + " must be 0.." + std::to_string(most) +
                         (codec == VideoCodec::h264 ? " for H.264" : " for VP9"));
    if (o.bitrate_kbps < 0 || o.bitrate_kbps > 1000000)
        throw InputError(what + "bitrate " + std::to_string(o.bitrate_kbps) +
                         " kbit/s must be 1..1000000 (0 = constant quality)");
    if (!o.preset.empty() && codec != VideoCodec::h264)
        throw InputError(what + "a speed preset ('" + o.preset + "') is for H.264 (.mp4) only");
    static const char* const presets[] = {"ultrafast", "superfast", "veryfast", "faster",  "fast",
                                          "medium",    "slow",      "slower",   "veryslow"};
    if (!o.preset.empty()) {
        bool known = false;
        for (const char* p : presets) known = known || o.preset == p;
        if (!known)
            throw InputError(
                what + "preset '" + o.preset +
                "': must be one of ultrafast, superfast, veryfast, faster, fast, medium, slow, slower, veryslow");
    }
}

VideoStream::VideoStream(OutputTransaction& outputs, const std::filesystem::path& video, double fps, cv::Size size,
                         const VideoOptions& options)
    : video_(video), size_(size) {
    const VideoCodec codec = video_codec_for(video);
    check_video_options(options, video);
    check_writable(video);
    // A registered temporary of a unique name beside the target (removed on failure or interrupt).
    const std::filesystem::path temp = outputs.stage_file(video);
    std::vector<std::string> args = {"ffmpeg",
                                     "-hide_banner",
                                     "-loglevel",
                                     "error",
                                     "-y",
                                     "-f",
                                     "rawvideo",
                                     "-pix_fmt",
                                     "bgr24",
                                     "-video_size",
                                     std::to_string(size.width) + "x" + std::to_string(size.height),
                                     "-framerate",
                                     number(fps),
                                     "-i",
                                     "pipe:0"};
    const std::vector<std::string> encoder = encoder_arguments(codec, options, size);
    args.insert(args.end(), encoder.begin(), encoder.end());
    // ffmpeg writes through a descriptor of ours, never by name: the temporary is ours to
    // create and remove, and an ffmpeg that outlives an interrupted run (it finishes on the
    // end of its input) writes into the removed file instead of creating it again.
    // /dev/fd/3 reopens the same file where +faststart reads it back.
    const int output = ::open(temp.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (output < 0)
        throw InputError("turntable video " + video.string() + ": cannot create " + temp.string() + ": " +
                         std::strerror(errno));
    args.push_back("file:/dev/fd/3");

    // A socket rather than a pipe: send() with MSG_NOSIGNAL reports a dead ffmpeg as an
    // error instead of raising SIGPIPE in the whole process.
    int fds[2];
    if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0)
        throw std::runtime_error("turntable video " + video.string() + ": socketpair: " + std::strerror(errno));
    log_ = std::tmpfile();
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, fds[1], 0);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    if (log_) posix_spawn_file_actions_adddup2(&actions, fileno(log_), 2);
    posix_spawn_file_actions_adddup2(&actions, output, 3);
    posix_spawnattr_t attributes;
    posix_spawnattr_init(&attributes);
    sigset_t none, defaults;
    sigemptyset(&none);
    sigemptyset(&defaults);
    sigaddset(&defaults, SIGPIPE);
    posix_spawnattr_setsigmask(&attributes, &none);  // interrupts held back by a commit stay ours
    posix_spawnattr_setsigdefault(&attributes, &defaults);
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
    std::vector<char*> argv;
    for (std::string& s : args) argv.push_back(s.data());
    argv.push_back(nullptr);
    const int spawned = posix_spawnp(&child_, "ffmpeg", &actions, &attributes, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attributes);
    ::close(fds[1]);
    ::close(output);
    input_ = fds[0];
    if (spawned != 0) {
        child_ = -1;
        fail(std::string("cannot run ffmpeg (apt-get install ffmpeg): ") + std::strerror(spawned));
    }
}

VideoStream::~VideoStream() {
    if (input_ >= 0) ::close(input_);
    if (child_ > 0) {
        kill(child_, SIGKILL);
        int status = 0;
        waitpid(child_, &status, 0);
    }
    if (log_) std::fclose(log_);
}

void VideoStream::fail(const std::string& what) {
    std::string said;
    if (log_ && child_ < 0) {
        std::fflush(log_);
        std::rewind(log_);
        char line[512];
        while (said.size() < 2000 && std::fgets(line, sizeof line, log_)) said += line;
        while (!said.empty() && (said.back() == '\n' || said.back() == '\r')) said.pop_back();
        for (char& c : said)
            if (c == '\n') c = ' ';
    }
    throw std::runtime_error("turntable video " + video_.string() + ": " + what + (said.empty() ? "" : ": " + said));
}

void VideoStream::add(const cv::Mat& bgr) {
    if (bgr.size() != size_ || bgr.type() != CV_8UC3)
        throw std::logic_error("video " + video_.string() + ": a frame of another size or type");
    const cv::Mat frame = bgr.isContinuous() ? bgr : bgr.clone();
    const char* data = reinterpret_cast<const char*>(frame.data);
    std::size_t left = frame.total() * frame.elemSize();
    while (left > 0) {
        const ssize_t sent = send(input_, data, left, MSG_NOSIGNAL);
        if (sent < 0 && errno == EINTR) continue;
        if (sent <= 0) {
            close();  // collects ffmpeg's exit and message
            fail("ffmpeg stopped reading frames");
        }
        data += sent;
        left -= static_cast<std::size_t>(sent);
    }
}

void VideoStream::close() {
    if (input_ >= 0) ::close(input_), input_ = -1;
    if (child_ <= 0) return;
    int status = 0;
    while (waitpid(child_, &status, 0) < 0 && errno == EINTR) {
    }
    child_ = -1;
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        fail("ffmpeg failed (" +
             (WIFEXITED(status) ? "exit status " + std::to_string(WEXITSTATUS(status))
                                : "signal " + std::to_string(WTERMSIG(status))) +
             ")");
}

}  // namespace foldcast::batch
