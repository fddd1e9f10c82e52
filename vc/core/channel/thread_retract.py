"""Thread cutting (G33) in the channel, fast retraction (LFON) and the channel's side of ESR.

A G33 block's axes follow the master spindle (``vc/core/interpolation/thread_cutting.py``); the
G33 blocks of one thread chain on from where the last one ended.  NC stop in G33 lets the block
run to its end, or with LFON lifts the tool at once; a rising $AC_ESR_TRIGGER does the same with
LFON, else starts the channel's ESR reaction (``vc/core/retraction/esr.py``), whose stop axes may
run on along the path for MD21380.  After a fast retraction the rest of the thread block and the
G33 blocks chained to it are dropped::

    G33 block ──spindle turning──▶ thread running ──end──▶ block end (the chain goes on from here)
    thread running ──NC stop or ESR trigger with LFON──▶ retract, the chain dropped, program stopped
    thread running ──ESR trigger without LFON──▶ run-on (MD21380) ──ESR braked the axes──▶ dropped
    thread running ──an axis braked off the thread──▶ contour lost, program stopped
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from vc.config import md_dictionary as MD
from vc.config.model import ChannelConfig
from vc.core.alarms import AlarmList
from vc.core.axis.axis import MachineAxis
from vc.core.axis.owner import Owner
from vc.core.channel.program_run import BlockPhase, ChannelState, ProgramRun, ProgramState, raise_block_alarm
from vc.core.channel.spindle_functions import SpindleFunctions
from vc.core.interpolation.thread_cutting import THREAD_SPINDLE_STANDS, ThreadSegment
from vc.core.program.block_plan import BlockPlan
from vc.core.retraction.esr import ChannelEsr
from vc.core.transforms.inclined_axis_control import InclinedAxisControl


class ThreadRetract:
    def __init__(self, run: ProgramRun, config: ChannelConfig, axes: Sequence[MachineAxis],
                 axes_by_name: dict[str, MachineAxis], spindles: SpindleFunctions, alarms: AlarmList, dt: float,
                 stop: Callable[[], None]):
        self.run = run
        self.config = config
        self.name = config.name
        self._axes = axes
        self._axes_by_name = axes_by_name
        self._spindles = spindles
        self._alarms = alarms
        self._dt = dt
        self._stop = stop  # the channel's NC stop
        self.esr: ChannelEsr | None = None  # fast retraction and ESR, given by the NCK
        self.inclined: InclinedAxisControl | None = None  # inclined-axis control (seed 000), given by the NCK
        self.thread_segment: ThreadSegment | None = None  # the running G33 block
        self._thread_chain: float | None = None  # spindle position where the last G33 block ended
        self._thread_interrupted = False  # an ESR trigger retracted from the running G33 block (LFON)
        self.esr_run_on_spindle: str | None = None  # the master spindle of a thread in the ESR's MD21380

    def esr_cycle(self, cycle: int) -> bool:
        """The running ESR reaction; True: MD21380 lets the stop axes' path run on in this cycle."""
        esr = self.esr
        path_runs_on = False
        if esr is not None and esr.running:
            esr.cycle(cycle, self.thread_segment or self.run.segment)
            path_runs_on = esr.path_runs_on(cycle)  # MD21380: the stop axes' path goes on
        # a thread's run-on needs its spindle turning through the alarms' interpolation stop [control]
        thread = self.thread_segment
        self.esr_run_on_spindle = thread.spindle.name if path_runs_on and thread is not None else None
        return path_runs_on

    def end_thread_functions(self) -> None:
        """Reset or program end: a running thread block stops, the modal synchronized actions end."""
        if self.thread_segment is not None:
            for axis in self.thread_segment.axes:
                axis.brake()
            self.thread_segment = None
        self._thread_chain = None
        self._thread_interrupted = False
        if self.esr is not None:
            self.esr.program_ended()

    def retract_functions(self, plan: BlockPlan, cycle: int) -> None:
        """The block's system variables, synchronized actions, POLFA and ESRS / ESRR, in this order."""
        esr = self.esr
        if plan.thread is None:
            self._thread_chain = None
        if esr is None:
            return
        esr.add_actions(plan.sync_actions)
        for axis, kind, value in plan.single_axis_retract:
            esr.single_axis_retract_command(axis, kind, value)
        for command in plan.drive_esr:
            drive = esr.nck.drives.get(command.axis)
            if drive is not None:
                drive.configure(command)  # [control] the drive acknowledges within the block
        for write in plan.variables:
            esr.write(write, cycle)
        self.esr_trigger(cycle)

    def esr_trigger(self, cycle: int) -> None:
        """React to a rising $AC_ESR_TRIGGER: fast retraction in G33 with LFON, else the ESR reaction."""
        esr = self.esr
        if esr is None or not esr.channel_trigger_pending:
            return
        esr.channel_trigger_pending = False
        if self.thread_segment is not None and self.run.modal.retract.enabled and not self._thread_interrupted:
            self.lift_fast(cycle)
            return
        interpolation = (self.thread_segment or self.run.segment) if self.run.phase is BlockPhase.INTERPOLATE else None
        esr.start_channel_reaction(cycle, [axis.name for axis in self._axes], interpolation, self.run.modal.retract,
                                   self._esr_delays(), self.inclined)
        if self.thread_segment is not None:
            # G33 without LFON: the retract axes have left the thread, the others follow the spindle on
            # for MD21380; the block is dropped when the ESR has braked them [control]
            if self.thread_segment.axes:
                self._thread_interrupted = True
            else:
                self._drop_thread_block()
        self.run.interrupt()

    def _esr_delays(self) -> tuple[float, float]:
        md = self.config.md
        return md.float(MD.ESR_DELAY_TIME1), md.float(MD.ESR_DELAY_TIME2)

    def lift_fast(self, esr_cycle: int | None) -> None:
        """G33 with LFON interrupted: retract; the thread axes that stay stop at once, or after an ESR
        trigger in ``esr_cycle`` when MD21380 / MD21381 say.  The rest of the thread block and the
        G33 blocks chained to it are dropped, so NC start goes on after the thread, where the seed's
        example tests ``IF $AC_LIFTFAST GOTOB MM_THREAD`` (L8356-8385) [INF]."""
        thread, esr, modal = self.thread_segment, self.esr, self.run.modal
        assert thread is not None and esr is not None
        esr.start_liftfast(modal.retract, modal.plane, thread, self.config.md.float(MD.LIFTFAST_DIST),
                           self.inclined, None if esr_cycle is None else (esr_cycle, self._esr_delays()))
        if esr_cycle is None or not thread.axes:
            self._drop_thread_block()
        else:
            self._thread_interrupted = True  # the thread runs on until the ESR brakes it
        self.run.state = ChannelState.INTERRUPTED
        self.run.program_state = ProgramState.STOPPED

    def _drop_thread_block(self) -> None:
        self.thread_segment = None
        self._thread_chain = None
        self._thread_interrupted = False
        self.run.plan = None
        self.run.phase = BlockPhase.DECODE
        self.run.block_index += 1
        self.run.leaving_thread_chain = True

    def start_thread(self, cycle: int) -> bool:
        """G33: the axes follow the master spindle; a standing spindle cannot cut a thread (alarm 65870).
        True: the thread block has ended at once, its block end follows."""
        plan, block = self.run.plan, self.run.current_block
        assert plan is not None and plan.thread is not None and block is not None
        master_name = self._spindles.master_spindle()
        master = self._spindles.spindles.get(master_name or "")
        if master is None or (master.axis.velocity == 0.0 and self._thread_chain is None):
            raise_block_alarm(self._alarms, self.name, THREAD_SPINDLE_STANDS, cycle, block, master_name or "-")
            self._stop()
            return False
        axes = [self._axes_by_name[name] for name in plan.targets]
        lead_axis = self._axes_by_name.get(plan.thread.lead_axis)
        lead_delta = plan.targets[lead_axis.name] - lead_axis.setpoint if lead_axis and lead_axis.name in plan.targets \
            else 0.0
        self.thread_segment = ThreadSegment.plan(axes, [plan.targets[axis.name] for axis in axes], lead_delta,
                                                 plan.thread, master.axis, self._thread_chain)
        self.run.phase = BlockPhase.INTERPOLATE
        return self.thread_cycle()

    def thread_cycle(self) -> bool:
        """One IPO cycle of the thread; True: the block has reached its end, its block end follows."""
        thread = self.thread_segment
        assert thread is not None
        if any(axis.owner is not Owner.PATH for axis in thread.axes):
            if self._thread_interrupted:
                self._drop_thread_block()  # the ESR braked the thread axes after MD21380
                return False
            for axis in thread.axes:
                if axis.owner is Owner.PATH:
                    axis.brake()  # braked off the thread (rapid stop): the others stop too, the contour is lost
            self.thread_segment = None
            self.run.phase = BlockPhase.CONTOUR_LOST
            self._stop()
            return False
        thread.cycle(self._dt)
        if thread.finished:
            for axis in thread.axes:
                axis.release()
            if self._thread_interrupted:
                self._drop_thread_block()  # ended in the ESR's run-on: the chain is left all the same
                return False
            self.thread_segment = None
            self._thread_interrupted = False
            self._thread_chain = thread.end_position
            self.run.phase = BlockPhase.BLOCK_END
            return True
        return False
