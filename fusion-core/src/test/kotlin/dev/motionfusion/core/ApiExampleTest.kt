package dev.motionfusion.core

import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.filter.MadgwickFilter
import dev.motionfusion.core.input.Recording
import dev.motionfusion.core.replay.ReplayListener
import dev.motionfusion.core.replay.ReplayStep
import dev.motionfusion.core.replay.Replayer
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.nio.file.Files
import java.nio.file.Path
import java.nio.file.Paths
import kotlin.math.PI

/**
 * docs/API.md's example: the block there is this file's [yawDegrees] line for line, and it runs: on the
 * repository's sample recording it gives the yaw of every step, as the replay does.
 */
class ApiExampleTest {
    // The example, exactly as docs/API.md shows it (between the markers).
    // example:start
    fun yawDegrees(path: Path): List<Double> {
        val filter = MadgwickFilter(FilterSettings(beta = 0.05))
        val yaw = ArrayList<Double>()
        Recording.open(path).use { recording ->
            recording.events().use { e ->
                while (e.next()) {
                    val stepped = filter.update(e.stream, e.timestampNs, e.values[0], e.values[1], e.values[2])
                    if (stepped && filter.isInitialised) yaw += Orientations.phoneAerospaceAngles(filter.orientation()).yaw * 180 / PI
                }
            }
        }
        return yaw
    }
    // example:end

    private fun repoFile(name: String): Path =
        listOf(Paths.get(name), Paths.get("..").resolve(name)).firstOrNull { Files.exists(it) } ?: throw AssertionError("$name not found")

    @Test
    fun `the document shows this file's example`() {
        val source = Files.readAllLines(repoFile("fusion-core/src/test/kotlin/dev/motionfusion/core/ApiExampleTest.kt"))
        val example = source.subList(source.indexOfFirst { it.trim() == "// example:start" } + 1, source.indexOfFirst { it.trim() == "// example:end" })
            .map { it.removePrefix("    ") }
        val doc = Files.readAllLines(repoFile("docs/API.md"))
        val start = doc.indexOf("```kotlin")
        assertTrue(start >= 0, "docs/API.md has no kotlin block")
        val block = doc.subList(start + 1, doc.subList(start + 1, doc.size).indexOf("```") + start + 1)
        assertEquals(example, block)
        assertTrue(block.size <= 14, "the example should stay short: ${block.size} lines")
    }

    @Test
    fun `the example gives the replay's yaw at every step`() {
        val sample = repoFile("samples/sim-figure8.csv.gz")
        val yaw = yawDegrees(sample)
        val replayed = ArrayList<Double>()
        Recording.open(sample).use { recording ->
            recording.events().use { events ->
                Replayer(FilterSettings(beta = 0.05)).run(events, recording.originNs, object : ReplayListener {
                    override fun step(step: ReplayStep) {
                        if (step.initialised) {
                            val o = step.orientation
                            replayed += Orientations.phoneAerospaceAngles(Quaternion(o[0], o[1], o[2], o[3])).yaw * 180 / PI
                        }
                    }
                })
            }
        }
        assertTrue(yaw.size > 1000, "${yaw.size} steps")
        assertEquals(replayed.size, yaw.size)
        for (i in yaw.indices) assertEquals(replayed[i], yaw[i], 1e-9, "step $i")
    }
}
