"""motions: the motion model, XML phase and Webots readers/writers, and the motion files the agent plays."""

from motions.convert import convert, to_webots, to_xml
from motions.errors import ConversionError, MotionFormatError
from motions.io import detect_format, dumps, load, loads, save
from motions.mirror import mirror_table
from motions.model import (WEBOTS, XML, JointTarget, Keyframe, KeyframeSource, Motion, MotionSource,
                           UnknownColumn)
from motions.validation import validate_motion
from motions.webots import dumps_webots, loads_webots
from motions.xml_phase import dumps_xml, loads_xml

__all__ = [
    "ConversionError", "JointTarget", "Keyframe", "KeyframeSource", "Motion", "MotionFormatError", "MotionSource",
    "UnknownColumn", "WEBOTS", "XML", "convert", "detect_format", "dumps", "dumps_webots",
    "dumps_xml", "load", "loads", "loads_webots", "loads_xml", "mirror_table", "save", "to_webots", "to_xml",
    "validate_motion",
]
