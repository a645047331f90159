package dev.motionfusion.core.replay

import dev.motionfusion.core.event.SessionStream

/**
 * Passes each replay step to [inner] with its time ([ReplayStep.timeS]) given by [timeS] of its timestamp instead of
 * the seconds since the recording's own origin: the rows put on another clock's timeline (`fusion replay --align`,
 * docs/SYNC.md). The filter still runs on the recording's own timestamps; only the rows' times change. The step is
 * changed in place (every listener after this one sees the new time). Reference streams pass unchanged.
 */
public class Retimed(private val inner: ReplayListener, private val timeS: (timestampNs: Long) -> Double) : ReplayListener {
    override fun step(step: ReplayStep) {
        step.timeS = timeS(step.timestampNs)
        inner.step(step)
    }

    override fun reference(stream: SessionStream, timestampNs: Long, values: DoubleArray): Unit = inner.reference(stream, timestampNs, values)
}
