package dev.motionfusion.app.stream

import dev.motionfusion.app.record.RecordingState
import dev.motionfusion.app.record.Recordings
import dev.motionfusion.core.session.RemoteStart
import dev.motionfusion.core.sync.ClockExchange

/**
 * A laptop in control, carried out by the recording service as the phone's own buttons are (docs/STREAMING.md, "Remote
 * control"): a start is Record ([startService]: the service started with the laptop's tag; why the system refused, or
 * null), a stop is Stop ([stopService]), a mark a marker of the running recording; the clock exchanges go into the
 * running recording's clock.csv.
 */
internal class RecordingRemote(
    private val recordings: Recordings,
    private val startService: (RemoteStart) -> String?,
    private val stopService: () -> Unit,
) : RemoteRecording {
    override fun start(start: RemoteStart): String? =
        if (recordings.isRecording) "already recording" else startService(start)

    override fun stop(): String? {
        if (!recordings.isRecording) return "not recording"
        stopService()
        return null
    }

    override fun mark(atNs: Long, label: String): String? =
        if (recordings.mark(atNs, label)) null else "not recording"

    override fun clockExchange(e: ClockExchange, laptopClock: String) {
        (recordings.state.value as? RecordingState.Active)?.clockExchange?.invoke(e, laptopClock)
    }
}
