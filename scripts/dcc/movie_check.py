"""Checks a cache's preview movies with outside decoders (scripts/movie-check.sh).

preview/movie.png: Pillow reads an animated PNG of FRAMES frames, each shown 1/FPS s,
looping. preview/movie.mp4, when ffprobe is installed: H.264, FRAMES frames at FPS.
"""
import json
import shutil
import subprocess
import sys
from pathlib import Path

from PIL import Image


def main():
    out, frames, fps = Path(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3])
    failures = []

    def check(ok, message):
        if not ok:
            failures.append(message)

    with Image.open(out / "preview" / "movie.png") as movie:
        check(movie.format == "PNG" and getattr(movie, "is_animated", False),
              f"movie.png is not an animated PNG ({movie.format})")
        check(movie.n_frames == frames, f"movie.png has {movie.n_frames} frames, not {frames}")
        check(movie.info.get("loop") == 0, f"movie.png loops {movie.info.get('loop')} times, not forever")
        for k in range(movie.n_frames):
            movie.seek(k)
            duration = movie.info.get("duration")
            check(duration is not None and abs(duration - 1000.0 / fps) < 0.02,
                  f"frame {k + 1} lasts {duration} ms, not {1000.0 / fps:.3f}")
        print(f"movie.png: {movie.n_frames} frames of {movie.size[0]}x{movie.size[1]} "
              f"at {1000.0 / fps:.3f} ms each (Pillow)")

    mp4 = out / "preview" / "movie.mp4"
    if shutil.which("ffprobe") is None:
        print("movie.mp4: no ffprobe on this machine, not checked")
    elif not mp4.is_file():
        failures.append("ffprobe is installed but there is no movie.mp4 (ffmpeg missing?)")
    else:
        probe = json.loads(subprocess.run(
            ["ffprobe", "-v", "error", "-select_streams", "v:0", "-count_frames",
             "-show_entries", "stream=codec_name,nb_read_frames,r_frame_rate",
             "-of", "json", str(mp4)],
            check=True, capture_output=True, text=True).stdout)["streams"][0]
        num, den = (float(x) for x in probe["r_frame_rate"].split("/"))
        check(probe["codec_name"] == "h264", f"movie.mp4 codec {probe['codec_name']}")
        check(int(probe["nb_read_frames"]) == frames,
              f"movie.mp4 has {probe['nb_read_frames']} frames, not {frames}")
        check(abs(num / den - fps) < 1e-3 * fps, f"movie.mp4 plays at {num / den} fps, not {fps}")
        print(f"movie.mp4: {probe['nb_read_frames']} frames at {num / den} fps (ffprobe)")

    for f in failures:
        print("FAILED:", f, file=sys.stderr)
    sys.exit(1 if failures else 0)


main()
