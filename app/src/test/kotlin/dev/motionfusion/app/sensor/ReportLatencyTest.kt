package dev.motionfusion.app.sensor

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test

/** The report latency while nothing is on screen, from the FIFO sizes devices report. */
class ReportLatencyTest {
    /** [n] sensors at [hz] each reporting the same FIFO counts. */
    private fun device(n: Int, reserved: Int, max: Int, hz: Double = 200.0) = List(n) { SensorFifo(reserved, max, hz) }

    /** The events of every batching sensor in [latencyUs] fit in [FIFO_SHARE] of the FIFO, by one of the two bounds. */
    private fun fits(sensors: List<SensorFifo>, latencyUs: Int): Boolean {
        val s = latencyUs / 1e6
        val batching = sensors.filter { it.maxEvents > 0 }
        val shared = batching.sumOf { it.eventsPerSecond * s } <= ReportLatency.FIFO_SHARE * batching.minOf { it.maxEvents } + 1e-6
        val reserved = batching.all { it.eventsPerSecond * s <= ReportLatency.FIFO_SHARE * it.reservedEvents + 1e-6 }
        return shared || reserved
    }

    @Test
    fun `a device without FIFO gets no batching`() {
        assertEquals(0, ReportLatency.choose(device(8, 0, 0)))
        assertEquals(0, ReportLatency.choose(emptyList()))
    }

    @Test
    fun `a small shared FIFO gives a short latency that leaves half of it free`() {
        // 8 streams at 200 Hz into one FIFO of 600 events: 1600 events/s, half the FIFO lasts 187.5 ms.
        val d = device(8, 0, 600)
        assertEquals(187_500, ReportLatency.choose(d))
        assertTrue(fits(d, ReportLatency.choose(d)))
    }

    @Test
    fun `a FIFO too small to be worth batching gives 0`() {
        // 8 × 200 Hz into 100 events: 31 ms, below the 50 ms minimum.
        assertEquals(0, ReportLatency.choose(device(8, 0, 100)))
    }

    @Test
    fun `a large FIFO is capped at a few seconds`() {
        assertEquals(ReportLatency.MAX_US, ReportLatency.choose(device(8, 0, 100_000)))
        assertEquals(5_000_000, ReportLatency.MAX_US)
    }

    @Test
    fun `reserved space that holds more than the shared bound is used, and still never overflows`() {
        // Each sensor keeps 600 events for itself (3 s at 200 Hz), the shared maximum is the same 600 for all:
        // shared, 600 / 1600 events/s = 0.375 s; reserved, 3 s; half of the larger: 1.5 s.
        val d = device(8, 600, 600)
        assertEquals(1_500_000, ReportLatency.choose(d))
        assertTrue(fits(d, ReportLatency.choose(d)))
    }

    @Test
    fun `the smallest FIFO and the fastest sensors decide, and sensors without FIFO are left out`() {
        val d = listOf(
            SensorFifo(0, 3000, 200.0), SensorFifo(0, 3000, 200.0), SensorFifo(0, 2000, 100.0), // shared: 2000 / 500 = 4 s
            SensorFifo(0, 0, 200.0), // a software sensor: delivers as it comes whatever is asked
        )
        assertEquals(2_000_000, ReportLatency.choose(d))
        assertTrue(fits(d, ReportLatency.choose(d)))
        // Faster sensors, shorter latency: at 500 Hz, 2000 / 1100 events/s × ½ ≈ 0.909 s.
        val fast = listOf(SensorFifo(0, 3000, 500.0), SensorFifo(0, 3000, 500.0), SensorFifo(0, 2000, 100.0))
        assertEquals(909_090, ReportLatency.choose(fast))
        assertTrue(fits(fast, ReportLatency.choose(fast)))
    }

    @Test
    fun `the rate a sensor delivers at is the requested one, or its fastest when that is slower`() {
        assertEquals(100.0, ReportLatency.eventsPerSecond(SamplingRate.Hz(100), 2_500), 1e-9)
        assertEquals(400.0, ReportLatency.eventsPerSecond(SamplingRate.Delay.FASTEST, 2_500), 1e-9)
        assertEquals(200.0, ReportLatency.eventsPerSecond(SamplingRate.Hz(500), 5_000), 1e-9)
        assertEquals(1000.0, ReportLatency.eventsPerSecond(SamplingRate.Delay.FASTEST, 0), 1e-9)
    }
}
