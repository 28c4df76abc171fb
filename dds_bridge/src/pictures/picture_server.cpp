#include "pictures/picture_server.h"

#include <algorithm>
#include <cctype>
#include <optional>

#include "macsim/dds/topics.h"
#include "macsim/dds/wire.h"
#include "macsim/images/image_files.h"
#include "macsim/render/camera_modes.h"
#include "typed_request.h"

namespace macsim {

namespace mm = macsim_msgs::msg::dds_;

namespace {

/// A picture request as the runner queues it: the scene is taken between two steps.
using PictureCall = TypedRequest<mm::PictureRequest_PubSubType>;

/// A file name of letters, digits, '_', '-' and '.', not starting with '.', at most 100 long.
bool safe_name(const std::string& name) {
  return !name.empty() && name.size() <= 100 && name[0] != '.' &&
         std::all_of(name.begin(), name.end(), [](unsigned char c) {
           return std::isalnum(c) || c == '_' || c == '-' || c == '.';
         });
}

}  // namespace

PictureServer::PictureServer(dds::Participant& participant, Runner& runner, std::string folder,
                             render::CameraIntrinsics size, std::size_t max_files)
    : runner_(runner),
      folder_(std::move(folder)),
      size_(size),
      admission_(kMaxInFlight, max_files),
      progress_([this](const Reply& reply) { service_.reply(reply); }) {
  // On the simulation thread: the scene is taken between two steps (the world only read).
  runner_.set_executor<PictureCall>([this](const PictureCall& call, const Command&, World& world) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      jobs_.push_back({call.message(), capture_scene(world), world.time()});
    }
    queued_.notify_one();
    return false;
  });
  if (!folder_.empty()) renderer_ = std::thread([this] { render_loop(); });
  service_.open(participant, {dds::topics::kPictureRequest, dds::topics::kPictureReply},
                [this](const Request& r, const dds::RequestId&) { accept(r); });
}

PictureServer::~PictureServer() {
  service_.close();
  runner_.set_executor<PictureCall>({});  // what is still queued runs nowhere
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  queued_.notify_all();
  if (renderer_.joinable()) renderer_.join();
}

void PictureServer::send(const Request& request, int code, const std::string& message, double time,
                         const std::string& file) {
  Reply reply;
  reply.client_id(request.client_id());
  reply.sequence_number(request.sequence_number());
  reply.code(code);
  reply.message(message);
  reply.sim_time(time);
  reply.file(file);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    replied_.remember(reply);
  }
  progress_.end(reply.client_id(), reply.sequence_number());
  service_.reply(reply);
}

void PictureServer::accept(const Request& r) {
  // A repeat of a request still waiting gets its progress (ERR_IN_PROGRESS) instead.
  if (!progress_.begin(r, "taking and rendering the picture '" + r.name() + "'")) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (const Reply* again = replied_.find(r)) {
      progress_.end(r.client_id(), r.sequence_number());
      service_.reply(*again);
      return;
    }
    if (replied_.forgotten(r)) {  // answered long ago: its reply is gone, it must not run again
      progress_.end(r.client_id(), r.sequence_number());
      service_.reply(replied_.forgotten_reply(r));
      return;
    }
    const bool pending = std::any_of(jobs_.begin(), jobs_.end(), [&](const Job& j) {
      return j.request.client_id() == r.client_id() &&
             j.request.sequence_number() == r.sequence_number();
    });
    if (pending) return;  // sent again while it is being rendered
  }
  if (folder_.empty()) {
    send(r, mm::ERR_NOT_APPLICABLE, "pictures are off: start macsim with --pictures DIR", 0, "");
    return;
  }
  if (!safe_name(r.name())) {
    send(r, mm::ERR_INVALID_ARGUMENT,
         "name: '" + r.name() + "' is not a file name (letters, digits, '_', '-', '.')", 0, "");
    return;
  }
  if (!r.camera_mode().empty() && !render::camera_mode_from_name(r.camera_mode())) {
    send(r, mm::ERR_INVALID_ARGUMENT, "camera_mode: unknown mode '" + r.camera_mode() + "'", 0, "");
    return;
  }
  std::optional<std::string> refused;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    refused = admission_.admit(r.name());
  }
  if (refused) {
    send(r, mm::ERR_LIMIT_REACHED, *refused, 0, "");
    return;
  }
  // The scene is taken between two steps, on the simulation thread.
  const bool pushed =
      runner_.push(request_command<PictureCall>(CommandSource::Pictures, r, "take_picture"));
  if (!pushed) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      admission_.done();
    }
    send(r, mm::ERR_LIMIT_REACHED, runner_.queue_full_message(), 0, "");
  }
}

void PictureServer::render_loop() {
  std::unique_ptr<render::OffscreenRenderer> renderer;
  std::string broken;
  while (true) {
    Job job;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      queued_.wait(lock, [this] { return stopping_ || !jobs_.empty(); });
      if (stopping_) return;
      job = std::move(jobs_.front());
      jobs_.pop_front();
    }
    const auto mode = render::camera_mode_from_name(
                          job.request.camera_mode().empty() ? "Follow" : job.request.camera_mode())
                          .value_or(render::CameraMode::Follow);
    const std::string file = folder_ + "/" + job.request.name() + ".png";
    int code = mm::ERR_OK;
    std::string message;
    try {
      if (!renderer)
        renderer = std::make_unique<render::OffscreenRenderer>(size_.width, size_.height);
      const cv::Mat image =
          renderer->render(job.scene, render::camera_pose(mode, job.scene), size_);
      if (!images::write_image(file, image)) {
        code = mm::ERR_BAD_FILE;
        message = "cannot write '" + file + "'";
      }
    } catch (const render::RenderError& e) {
      code = mm::ERR_NOT_APPLICABLE;
      message = std::string("cannot render: ") + e.what();
    } catch (const images::CodecsUnavailable& e) {
      code = mm::ERR_NOT_APPLICABLE;
      message = std::string("cannot write pictures: ") + e.what();
    }
    job.scene = Scene{};  // its place is free before the reply goes out
    {
      std::lock_guard<std::mutex> lock(mutex_);
      admission_.done();
    }
    send(job.request, code, message, job.time, code == mm::ERR_OK ? file : "");
  }
}

}  // namespace macsim
