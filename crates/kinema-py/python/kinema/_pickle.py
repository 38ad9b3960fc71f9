"""What ``pickle.loads`` calls to rebuild a :class:`~kinema.Robot` or a
:class:`~kinema.Scene` from the description it pickled as."""

from ._kinema import Robot, Scene


def robot_from_state(state: dict) -> Robot:
    return Robot._from_state(state)


def scene_from_state(state: dict) -> Scene:
    return Scene._from_state(state)
