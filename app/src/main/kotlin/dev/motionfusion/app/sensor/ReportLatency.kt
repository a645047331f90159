package dev.motionfusion.app.sensor

/**
 * One registered sensor's hardware FIFO as the device reports it (`Sensor.getFifoReservedEventCount`,
 * `getFifoMaxEventCount`), and the events per second it delivers at the registered rate.
 */
internal data class SensorFifo(val reservedEvents: Int, val maxEvents: Int, val eventsPerSecond: Double) {
    init {
        require(reservedEvents >= 0 && maxEvents >= 0) { "FIFO counts must be ≥ 0, were $reservedEvents and $maxEvents" }
        require(eventsPerSecond > 0 && eventsPerSecond.isFinite()) { "events per second must be > 0, was $eventsPerSecond" }
    }
}

/**
 * The `maxReportLatencyUs` the capture registers with while nothing is on screen: as long as the
 * sensors' FIFO can hold at the registered rate, with a margin, so that it never overflows.
 *
 * A device may share one FIFO among its sensors; [SensorFifo.maxEvents] is then that FIFO's size
 * for each of them, and [SensorFifo.reservedEvents] the part kept for the one sensor. Two bounds are
 * safe, so the larger one is used:
 * - shared: the smallest reported maximum holds the events of every batching sensor together,
 *   `min(maxEvents) / Σ eventsPerSecond`;
 * - reserved: each sensor's reserved part holds its own events, `min(reservedEvents / eventsPerSecond)`.
 * Only [FIFO_SHARE] of that is used (rates are hints: a device may deliver faster than asked),
 * capped at [MAX_US]; below [MIN_US] batching is not worth it and the result is 0. Sensors without a
 * FIFO (`maxEvents` 0) deliver each event as it comes whatever is asked and are left out; with none
 * that has one, the result is 0.
 */
internal object ReportLatency {
    /** The part of the FIFO a batch may fill. */
    const val FIFO_SHARE = 0.5

    /** 5 s: the longest a batch is held, whatever the FIFO. */
    const val MAX_US = 5_000_000

    /** 50 ms: a shorter latency saves too little to be worth a wider reorder window. */
    const val MIN_US = 50_000

    fun choose(sensors: Collection<SensorFifo>): Int {
        val batching = sensors.filter { it.maxEvents > 0 }
        if (batching.isEmpty()) return 0
        val shared = batching.minOf { it.maxEvents } / batching.sumOf { it.eventsPerSecond }
        val reserved = batching.minOf { it.reservedEvents / it.eventsPerSecond }
        val us = minOf(FIFO_SHARE * maxOf(shared, reserved) * 1e6, MAX_US.toDouble())
        return if (us < MIN_US) 0 else us.toInt()
    }

    /**
     * Events per second a sensor delivers when registered at [rate]: the nominal rate, or the
     * sensor's fastest (`minDelayUs`) when that is slower or "fastest" is asked (1 kHz when the sensor
     * does not say).
     */
    fun eventsPerSecond(rate: SamplingRate, minDelayUs: Int): Double {
        val fastest = if (minDelayUs > 0) minDelayUs else 1_000
        return 1e6 / maxOf(rate.nominalPeriodUs, fastest)
    }
}
