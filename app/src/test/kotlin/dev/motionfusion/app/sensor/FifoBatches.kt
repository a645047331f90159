package dev.motionfusion.app.sensor

import dev.motionfusion.core.event.SessionStream

/**
 * Events as sensors with hardware FIFOs deliver them: each stream's events gathered for
 * [latencyNs] and handed over whole, one stream's batch after another's, each stream at its own
 * phase ([phaseNs], 0 ≤ phase < latency; equal phases: a shared FIFO flushed at once, the
 * streams' batches in [order]). An event is delivered at the latest [latencyNs] after its timestamp.
 */
internal object FifoBatches {
    class Batch<E>(val deliveredNs: Long, val stream: SessionStream, val events: List<E>)

    fun <E> of(
        events: List<E>, stream: (E) -> SessionStream, timeNs: (E) -> Long, latencyNs: Long,
        phaseNs: (SessionStream) -> Long, order: List<SessionStream> = SensorStreams.all,
    ): List<Batch<E>> {
        val out = ArrayList<Batch<E>>()
        for ((s, list) in events.groupBy(stream)) {
            val phase = phaseNs(s)
            require(phase in 0 until latencyNs) { "phase must be in [0, latency)" }
            // The batch delivered at k·latency + phase holds the events after the previous delivery, up to it.
            for ((k, batch) in list.groupBy { Math.floorDiv(timeNs(it) - phase + latencyNs - 1, latencyNs) }) {
                out += Batch(k * latencyNs + phase, s, batch)
            }
        }
        return out.sortedWith(compareBy<Batch<E>> { it.deliveredNs }.thenBy { order.indexOf(it.stream) })
    }
}
