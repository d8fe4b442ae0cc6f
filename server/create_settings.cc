#include "server/create_settings.h"

namespace viscera::server {

double CreateSettings::FrameMpixPerS() const {
  return frame_rate_hz <= 0.0 ? 0.0 : 1e-6 * frame_rate_hz * frame_width * frame_height;
}

FrameStreamConfig CreateSettings::FrameStream(const ServerConfig& config) const {
  FrameStreamConfig frames;
  frames.rate_hz = frame_rate_hz;
  frames.lease_s = config.frame_lease_s;
  frames.adaptive = config.adaptive_frames;
  frames.options.width = frame_width;
  frames.options.height = frame_height;
  frames.options.jpeg_quality = jpeg_quality;
  frames.options.skin = skin;
  frames.options.skin_options.parametric.sides = config.skin_sides;
  frames.options.skin_options.convolution.sides = config.skin_sides;
  return frames;
}

CreateSettings ResolveCreateSettings(const viscera_proto::session_request_t& request,
                                     const ServerConfig& config) {
  CreateSettings s;
  s.rate_hz = request.rate_hz != 0.0 ? request.rate_hz : config.rate_hz;
  s.skeleton_rate_hz =
      request.skeleton_rate_hz != 0.0 ? request.skeleton_rate_hz : config.skeleton_rate_hz;
  s.frame_rate_hz = request.frame_rate_hz != 0.0 ? request.frame_rate_hz : config.frame_rate_hz;
  s.frame_width = request.frame_width > 0 ? request.frame_width : config.frame_width;
  s.frame_height = request.frame_height > 0 ? request.frame_height : config.frame_height;
  s.jpeg_quality = request.jpeg_quality > 0 ? request.jpeg_quality : config.jpeg_quality;
  s.skin = !request.skin.empty() ? request.skin : config.skin;
  return s;
}

}  // namespace viscera::server
