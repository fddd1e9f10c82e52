"""The channel's shared run state: NC stop's state half and the end of a program."""

from __future__ import annotations

from vc.core.channel.program_run import BlockPhase, ChannelState, Mode, ProgramRun, ProgramState
from vc.core.program.block_plan import BlockPlan
from vc.core.program.program import parse_program


def running() -> ProgramRun:
    run = ProgramRun()
    run.blocks = parse_program("G1 X10 F100\nG91\nM30")
    run.block_index = 1
    run.current_block = run.blocks[1]
    run.phase = BlockPhase.INTERPOLATE
    run.plan = BlockPlan()
    run.started_in = Mode.MDA
    run.state = ChannelState.ACTIVE
    run.program_state = ProgramState.RUNNING
    return run


def test_interrupt_stops_an_active_program_and_brakes_on_the_path() -> None:
    run = running()
    run.interrupt()
    assert (run.state, run.program_state, run.stopping) == (ChannelState.INTERRUPTED, ProgramState.STOPPED, True)
    assert run.block_index == 1 and run.phase is BlockPhase.INTERPOLATE  # NC start goes on in the same block


def test_interrupt_leaves_a_channel_in_reset_alone() -> None:
    run = ProgramRun()
    run.interrupt()
    assert (run.state, run.program_state, run.stopping) == (ChannelState.RESET, ProgramState.ABORTED, False)


def test_end_aborts_the_program_and_resets_the_modal_state() -> None:
    run = running()
    run.modal.absolute = False
    run.stopping = True
    run.end()
    assert (run.state, run.program_state, run.started_in) == (ChannelState.RESET, ProgramState.ABORTED, None)
    assert (run.blocks, run.block_index, run.current_block, run.plan) == ((), 0, None, None)
    assert run.phase is BlockPhase.DECODE and not run.stopping and run.modal.absolute
