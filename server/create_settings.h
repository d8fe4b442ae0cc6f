#pragma once
/// What a create asks for with the server's defaults filled in: the one place where a 0 (or
/// "") in a create means "the server's default".
#include <string>

#include <viscera_proto/session_request_t.hpp>

#include "server/frame_streamer.h"
#include "server/server_config.h"

namespace viscera::server {

struct CreateSettings {
  double rate_hz = 0.0;                   ///< mechanics rate (Hz); 0: the scene's
  double skeleton_rate_hz = 0.0;          ///< skeleton_state_t per second; <= 0: none
  double frame_rate_hz = 0.0;             ///< frames per second; <= 0: no frames
  int frame_width = 0, frame_height = 0;  ///< pixels
  int jpeg_quality = 0;
  std::string skin;

  /// The frame stream's pixels per second (megapixels; 0 without frames).
  double FrameMpixPerS() const;
  /// The render thread's settings (rate, size, quality, skin; lease and skin sides from
  /// `config`).
  FrameStreamConfig FrameStream(const ServerConfig& config) const;
};

/// `request`'s settings, each 0 (or "") replaced by `config`'s default.
CreateSettings ResolveCreateSettings(const viscera_proto::session_request_t& request,
                                     const ServerConfig& config);

}  // namespace viscera::server
