package dev.motionfusion.app.record

import dev.motionfusion.core.event.SessionStream
import java.io.IOException
import java.util.concurrent.CopyOnWriteArrayList

/** A sink that keeps what it is given in memory (timestamps and first values) and can fail on cue. */
internal class MemorySink(private val failAfterRows: Long = Long.MAX_VALUE, private val clock: () -> Long = System::nanoTime) : SessionSink {
    val times = ArrayList<Long>()
    val streams = ArrayList<SessionStream>()
    val firstValues = ArrayList<Float>()
    val fusedTimes = ArrayList<Long>()
    val fusedW = ArrayList<Double>()
    val flushes = CopyOnWriteArrayList<Long>()
    @Volatile var finished: RecordingEnd? = null
    @Volatile var abandoned = false

    override fun raw(stream: SessionStream, timestampNs: Long, accuracy: Int, values: FloatArray, offset: Int) {
        if (times.size.toLong() >= failAfterRows) throw IOException("No space left on device")
        times += timestampNs
        streams += stream
        firstValues += values[offset]
    }

    val diagnosticTimes = ArrayList<Long>()

    override fun diagnostics(t: Long, bx: Double, by: Double, bz: Double, rest: Boolean, mag: Boolean, acc: Boolean) {
        diagnosticTimes += t
    }

    override fun fused(timestampNs: Long, q: DoubleArray, offset: Int) {
        fusedTimes += timestampNs
        fusedW += q[offset]
    }

    val markers = CopyOnWriteArrayList<Pair<Long, String>>()

    override fun marker(timestampNs: Long, label: String) {
        markers += timestampNs to label
    }

    val checkpoints = CopyOnWriteArrayList<dev.motionfusion.core.session.ClockAnchor>()

    override fun checkpoint(anchor: dev.motionfusion.core.session.ClockAnchor) {
        checkpoints += anchor
    }

    override fun flush() {
        flushes += clock()
    }

    override fun finish(end: RecordingEnd) {
        finished = end
    }

    override fun abandon(end: RecordingEnd) {
        abandoned = true
    }
}
