"""The firmware images as their folders describe them (bsp/mspm0/images/<preset>/image.cmake and options.cmake),
for the Python checks: which images there are and what each one is, so a check asks "does this image count the
state of charge" instead of matching preset names, and an image added as a folder is checked like the others.

    import image_descriptions
    for image in image_descriptions.load():
        image.preset, image.chip, image.board, image.family, image.device, image.options["FW_SOC"]
"""
import pathlib
import re
from dataclasses import dataclass, field

ROOT = pathlib.Path(__file__).resolve().parents[1]
IMAGES_DIR = ROOT / "bsp" / "mspm0" / "images"

# The config headers whose `#ifndef NAME / #define NAME value` pairs are the options' defaults (the list
# options.cmake's header names).
CONFIG_HEADERS = ["firmware/sched/config.hpp", "firmware/core/config.hpp", "firmware/app/config.hpp",
                  "firmware/drivers/bq769x2/config.hpp", "bsp/mspm0/config.hpp"]


def _defaults():
    defaults = {}
    for header in CONFIG_HEADERS:
        text = (ROOT / header).read_text()
        for m in re.finditer(r"#ifndef (\w+)\s*\n#define \1 (\S+)", text):
            defaults[m.group(1)] = m.group(2)
    return defaults


DEFAULTS = _defaults()


@dataclass
class Image:
    preset: str
    chip: str
    board: str   # board kind: images/common/board_<kind>.cpp
    family: str  # bq769x2 | bq79616 | bq4050
    device: str
    options: dict = field(default_factory=dict)
    pack: str = ""  # the pack file it builds from (BMS_IMAGE_PACK: firmware/app/packs/<pack>.yaml)

    def option(self, name):
        return self.options.get(name, DEFAULTS.get(name))

    @property
    def output(self):
        """'slcan' on the L1306 boards' back-channel UART, 'can' on the G3507 boards."""
        return "slcan" if self.board.endswith("_slcan") else "can"

    @property
    def has_current(self):
        return self.family != "bq79616"  # the BQ79616 has no current input

    @property
    def counts_soc(self):
        """The image counts the state of charge itself (the BQ769x family with FW_SOC; the BQ4050's gauge
        computes its own)."""
        return self.family == "bq769x2" and self.option("FW_SOC") != "0"

    @property
    def gauge_soc(self):
        return self.family == "bq4050"

    @property
    def balances(self):
        return self.family == "bq79616" or (self.family == "bq769x2" and self.option("FW_BQ769X_BALANCE") != "0")

    @property
    def cells(self):
        """Cells per board, from the image's pack file (its top-level `cells:`)."""
        text = (ROOT / "firmware" / "app" / "packs" / f"{self.pack}.yaml").read_text()
        return int(re.search(r"^cells:\s*(\d+)", text, re.M).group(1))


def _sets(text):
    """set(NAME value...) calls of a CMake file, comments dropped."""
    text = re.sub(r"#[^\n]*", "", text)
    return {m.group(1): m.group(2).split() for m in re.finditer(r"set\(\s*(\w+)\s+([^)]*)\)", text)}


def load(images_dir=IMAGES_DIR):
    images = []
    for description in sorted(pathlib.Path(images_dir).glob("*/image.cmake")):
        folder = description.parent
        d = _sets(description.read_text())
        options_sets = _sets((folder / "options.cmake").read_text())
        options = dict(item.partition("=")[::2] for item in options_sets.get("BMS_IMAGE_OPTIONS", []))
        images.append(Image(folder.name, d["BMS_IMAGE_CHIP"][0], d["BMS_IMAGE_BOARD"][0], d["BMS_IMAGE_FAMILY"][0],
                            d["BMS_IMAGE_DEVICE"][0], options, options_sets["BMS_IMAGE_PACK"][0]))
    return images


def by_preset(images_dir=IMAGES_DIR):
    return {image.preset: image for image in load(images_dir)}


if __name__ == "__main__":
    for image in load():
        print(image.preset, image.chip, image.board, image.family, image.device, image.output, image.cells,
              "soc" if image.counts_soc else "-", "balances" if image.balances else "-")
