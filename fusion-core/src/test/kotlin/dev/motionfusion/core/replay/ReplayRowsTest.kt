package dev.motionfusion.core.replay

import dev.motionfusion.core.event.RowEvents
import dev.motionfusion.core.event.SensorEvents
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.input.Recording
import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulationSettings
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.nio.file.Files
import java.nio.file.Path
import java.util.Locale

/** A table replayed row by row gives exactly the steps and counts of the same table replayed event by event. */
class ReplayRowsTest {
    @TempDir
    lateinit var dir: Path

    /** The same events with the row interface hidden: the replay then goes event by event. */
    private class EventByEvent(inner: SensorEvents) : SensorEvents by inner

    private fun steps(events: SensorEvents, originNs: Long?): Pair<List<String>, ReplayCounts> {
        val out = ArrayList<String>()
        val counts = events.use {
            Replayer(FilterSettings()).run(it, originNs, object : ReplayListener {
                override fun step(step: ReplayStep) {
                    out += "${step.timestampNs} ${step.timeS.toRawBits()} ${step.initialised} " +
                        step.orientation.joinToString { q -> q.toRawBits().toString() } + " " + step.specificForce.joinToString { a -> a.toRawBits().toString() }
                }
            })
        }
        return out to counts
    }

    @Test
    fun `row steps equal event steps, with and without magnetometer`() {
        val samples = MotionSimulator(SimulationSettings(durationS = 30.0, rateHz = 200.0)).run()
        for (mag in listOf(true, false)) {
            val file = dir.resolve("t-$mag.csv")
            Files.newBufferedWriter(file).use { w ->
                w.write(if (mag) "t_s,gx,gy,gz,ax,ay,az,mx,my,mz\n" else "t_s,gx,gy,gz,ax,ay,az\n")
                for ((i, s) in samples.withIndex()) {
                    // A gap of 2 s and a step back in time, so the filter's skips are compared too.
                    val t = s.timestampNs * 1e-9 + (if (i > 3000) 2.0 else 0.0) - (if (i == 4000) 0.01 else 0.0)
                    val v = listOf(s.gyro.x, s.gyro.y, s.gyro.z, s.acc.x, s.acc.y, s.acc.z) + (if (mag) listOf(s.mag.x, s.mag.y, s.mag.z) else emptyList())
                    w.write(String.format(Locale.ROOT, "%.6f", t) + v.joinToString("") { "," + it.toFloat() } + "\n")
                }
            }
            Recording.open(file).use { rec ->
                val rows = rec.events()
                assertTrue(rows is RowEvents)
                val (rowSteps, rowCounts) = steps(rows, rec.originNs)
                val (eventSteps, eventCounts) = steps(EventByEvent(rec.events()), rec.originNs)
                assertEquals(samples.size, rowSteps.size)
                assertEquals(eventCounts, rowCounts)
                assertEquals(eventSteps, rowSteps)
            }
        }
    }

    @Test
    fun `empty magnetometer fields are no reading, on both paths`() {
        // A magnetometer at a third of the table's rate: its fields empty on two rows of three.
        val samples = MotionSimulator(SimulationSettings(durationS = 10.0, rateHz = 150.0)).run()
        val file = dir.resolve("sparse.csv")
        Files.newBufferedWriter(file).use { w ->
            w.write("t_s,gx,gy,gz,ax,ay,az,mx,my,mz\n")
            for ((i, s) in samples.withIndex()) {
                val v = listOf(s.gyro.x, s.gyro.y, s.gyro.z, s.acc.x, s.acc.y, s.acc.z).joinToString("") { "," + it.toFloat() }
                val m = if (i % 3 == 0) listOf(s.mag.x, s.mag.y, s.mag.z).joinToString("") { "," + it.toFloat() } else ",,,"
                w.write(String.format(Locale.ROOT, "%.6f", s.timestampNs * 1e-9) + v + m + "\n")
            }
        }
        Recording.open(file).use { rec ->
            val (rowSteps, rowCounts) = steps(rec.events(), rec.originNs)
            val (eventSteps, eventCounts) = steps(EventByEvent(rec.events()), rec.originNs)
            assertEquals((samples.size + 2L) / 3, rowCounts.magnetometer, "one reading in three rows")
            assertEquals(samples.size * 2L + rowCounts.magnetometer, rowCounts.events)
            assertEquals(eventCounts, rowCounts)
            assertEquals(eventSteps, rowSteps)
            assertTrue(rowSteps.last().split(' ')[2] == "true", "the filter has an orientation")
        }
    }
}
