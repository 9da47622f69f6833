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

# Option defaults the checks below ask about (firmware/app/config.hpp, firmware/drivers/bq769x2/config.hpp).
DEFAULTS = {"FW_SOC": "1", "FW_BQ769X_BALANCE": "1", "FW_CAN_TI_LAYOUT": "1"}
# Cells a device's EVM pack connects (firmware/app/packs/*.yaml), and whether it measures the pack current.
DEVICE_CELLS = {"bq76952": 16, "bq76907": 7, "bq79616": 16, "bq4050": 4}


@dataclass
class Image:
    preset: str
    chip: str
    board: str   # board kind: images/common/board_<kind>.cpp
    family: str  # bq769x2 | bq79616 | bq4050
    device: str
    options: dict = field(default_factory=dict)

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
        return DEVICE_CELLS[self.device]


def _sets(text):
    """set(NAME value...) calls of a CMake file, comments dropped."""
    text = re.sub(r"#[^\n]*", "", text)
    return {m.group(1): m.group(2).split() for m in re.finditer(r"set\(\s*(\w+)\s+([^)]*)\)", text)}


def load(images_dir=IMAGES_DIR):
    images = []
    for description in sorted(pathlib.Path(images_dir).glob("*/image.cmake")):
        folder = description.parent
        d = _sets(description.read_text())
        options = {}
        options_file = folder / "options.cmake"
        if options_file.exists():
            for item in _sets(options_file.read_text()).get("BMS_IMAGE_OPTIONS", []):
                name, _, value = item.partition("=")
                options[name] = value
        images.append(Image(folder.name, d["BMS_IMAGE_CHIP"][0], d["BMS_IMAGE_BOARD"][0], d["BMS_IMAGE_FAMILY"][0],
                            d["BMS_IMAGE_DEVICE"][0], options))
    return images


def by_preset(images_dir=IMAGES_DIR):
    return {image.preset: image for image in load(images_dir)}


if __name__ == "__main__":
    for image in load():
        print(image.preset, image.chip, image.board, image.family, image.device, image.output,
              "soc" if image.counts_soc else "-", "balances" if image.balances else "-")
