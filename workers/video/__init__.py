"""Episode video: an editor page's screencast encoded as H.264 MP4 off the event loop (``EpisodeRecorder``)."""

from workers.video._encoder import VideoEncoder
from workers.video._periods import FramePeriods, Timed
from workers.video._recorder import EpisodeRecorder

__all__ = ["EpisodeRecorder", "FramePeriods", "Timed", "VideoEncoder"]
