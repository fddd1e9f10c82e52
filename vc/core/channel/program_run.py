"""The channel and program state and where the program stands: what the channel's parts share.

Channel and program states (DB21.DBX35.x)::

    RESET / aborted ──NC start (AUTO: selected program, MDA: MDA buffer)──▶ ACTIVE / running
    ACTIVE / running ──NC stop, M0, alarm with interrupt──▶ INTERRUPTED / stopped
    INTERRUPTED / stopped ──mode change (e.g. to JOG)──▶ INTERRUPTED / interrupted
    INTERRUPTED ──NC start (in the mode the program was started in)──▶ ACTIVE / running
    any ──reset, M2, M30──▶ RESET / aborted

Observers see them as two state machines, ``CHANNEL_STATES`` and ``PROGRAM_STATES``.

The :class:`~vc.core.channel.channel.Channel` makes these transitions on its commands; its parts
(block execution, the spindle functions, thread cutting and the ESR) read and change the one
:class:`ProgramRun` it owns, so each sees the block, the phase and the state the others left.
"""

from __future__ import annotations

from enum import Enum

from vc.core.alarms import AlarmList
from vc.core.interpolation.path import PathSegment
from vc.core.interpolation.tool_path import ToolPathSegment
from vc.core.program.block_plan import BlockPlan, ModalState
from vc.core.program.program import Block
from vc.core.state_machine import Instance, StateMachine, states, transitions


class ChannelState(Enum):
    RESET = "reset"
    ACTIVE = "active"
    INTERRUPTED = "interrupted"


class ProgramState(Enum):
    ABORTED = "aborted"
    RUNNING = "running"
    WAITING = "waiting"
    STOPPED = "stopped"
    INTERRUPTED = "interrupted"


CHANNEL_STATES: StateMachine[ProgramRun] = StateMachine(
    __name__, "channel", "Channel state (DB21.DBX35.5-35.7)", Instance.CHANNEL,
    states(*ChannelState),
    transitions(("RESET", "ACTIVE", "NC start"), ("ACTIVE", "INTERRUPTED", "NC stop, an alarm"),
                ("RESET", "INTERRUPTED", "NC start, and an alarm of the first block in the same cycle"),
                ("INTERRUPTED", "ACTIVE", "NC start"), ("ACTIVE", "RESET", "program end, reset"),
                ("INTERRUPTED", "RESET", "reset")),
    read=lambda run: run.state)

PROGRAM_STATES: StateMachine[ProgramRun] = StateMachine(
    __name__, "program", "Program state (DB21.DBX35.0-35.4)", Instance.CHANNEL,
    states(*ProgramState),
    transitions(("ABORTED", "RUNNING", "NC start"), ("RUNNING", "ABORTED", "program end, reset"),
                ("ABORTED", "STOPPED", "NC start, and an alarm of the first block in the same cycle"),
                ("RUNNING", "WAITING", "read-in disable DB21.DBX6.1"), ("WAITING", "RUNNING", "read-in enabled"),
                ("RUNNING", "STOPPED", "NC stop, an alarm"), ("STOPPED", "RUNNING", "NC start"),
                ("STOPPED", "INTERRUPTED", "another mode selected"),
                ("INTERRUPTED", "RUNNING", "back in the mode, NC start"),
                ("STOPPED", "ABORTED", "reset"), ("INTERRUPTED", "ABORTED", "reset")),
    read=lambda run: run.program_state)


class BlockPhase(Enum):
    DECODE = "decode"
    INTERPOLATE = "interpolate"
    BLOCK_END = "block_end"
    DWELL = "dwell"
    REFERENCE = "reference"  # G74: waiting until the programmed axes are referenced
    SPINDLE = "spindle"  # the block's gear change, M70, or the spindle speed before machining
    AUXILIARY = "auxiliary"  # the functions output before the motion wait for the PLC's acknowledgement
    CONTOUR_LOST = "contour_lost"  # an axis was braked off the path: NC start cannot continue


class Mode(Enum):
    AUTO = "AUTO"
    MDA = "MDA"
    JOG = "JOG"


class ProgramRun:
    """The channel and program state, the modal state, the program and the block in progress."""

    def __init__(self) -> None:
        self.state: ChannelState = ChannelState.RESET
        self.program_state: ProgramState = ProgramState.ABORTED
        self.modal = ModalState()
        self.started_in: Mode | None = None
        self.blocks: tuple[Block, ...] = ()
        self.block_index = 0
        self.leaving_thread_chain = False  # after a fast retraction: skip the chain's other G33 blocks
        self.current_block: Block | None = None
        self.phase = BlockPhase.DECODE
        self.plan: BlockPlan | None = None
        self.segment: PathSegment | ToolPathSegment | None = None  # the path of the running block
        self.stop_after_block = False
        self.stopping = False  # braking on the path after NC stop / an alarm
        self.aborting = False  # braking on the path after a reset

    def interrupt(self) -> None:
        """The running program stops (braking on the path) and can continue with NC start."""
        if self.state is ChannelState.ACTIVE:
            self.state = ChannelState.INTERRUPTED
            self.program_state = ProgramState.STOPPED
            self.stopping = True

    def end(self) -> None:
        """Reset or program end: the channel in reset, the program aborted, the modal state reset."""
        self.state = ChannelState.RESET
        self.program_state = ProgramState.ABORTED
        self.started_in = None
        self.blocks = ()
        self.block_index = 0
        self.leaving_thread_chain = False
        self.current_block = None
        self.phase = BlockPhase.DECODE
        self.plan = None
        self.stop_after_block = False
        self.stopping = False
        self.modal.reset()


def raise_block_alarm(alarms: AlarmList, channel: str, number: int, cycle: int, block: Block, *parameters: object,
                      axis: str = "") -> None:
    """An alarm of the block ``block`` of channel ``channel``: the channel and the block's label first."""
    alarms.raise_alarm(number, cycle, channel, block.label, *parameters, channel=channel, axis=axis)
