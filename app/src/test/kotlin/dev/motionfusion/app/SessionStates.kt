package dev.motionfusion.app

import dev.motionfusion.app.sessions.AngleSeries
import dev.motionfusion.app.sessions.RateSeries
import dev.motionfusion.app.sessions.SessionDetailUiState
import dev.motionfusion.app.sessions.SessionItem
import dev.motionfusion.app.sessions.SessionSummary
import dev.motionfusion.app.sessions.StreamSummary
import dev.motionfusion.app.ui.PlotMarker
import java.io.File
import kotlin.math.sin

/** Sessions-list and session-detail states made by hand, for the screens' tests. */
internal object SessionStates {
    /** A session of [seconds] s at [hz] (magnetometer and rotation vectors at half of it), started at [wallMs]. */
    fun summary(name: String, seconds: Long, hz: Double, wallMs: Long, recovered: Boolean = false): SessionSummary {
        val rows = (seconds * hz).toLong()
        return SessionSummary(
            name = name, startWallClockMs = wallMs, durationNs = seconds * 1_000_000_000L, sizeBytes = rows * 210,
            streams = listOf(
                StreamSummary("accelerometer", rows, hz), StreamSummary("gyroscope", rows, hz),
                StreamSummary("magnetometer", rows / 2, hz / 2), StreamSummary("rotation_vector", rows / 2, hz / 2),
                StreamSummary("game_rotation_vector", rows / 2, hz / 2 - 0.4),
            ),
            fusedRows = rows, recovered = recovered,
        )
    }

    /** Four sessions in [root], one recovered, and one that cannot be read. */
    fun items(root: File) = listOf(
        summary("walk to the station", 754, 200.0, 1_795_688_100_000L),
        summary("session_2026-11-26_13-05-00", 62, 100.0, 1_795_698_300_000L, recovered = true),
        summary("session_2026-11-26_09-15-00", 1830, 400.0, 1_795_684_500_000L),
        summary("bike, handlebar mount", 2710, 200.0, 1_795_600_000_000L),
    ).map { SessionItem(File(root, it.name), it, null) } +
        SessionItem(File(root, "broken"), null, "meta.json:3:14: expected a number")

    /** [name], a 754-s walk: angles, three markers, each stream's rate in 1-s bins. */
    fun detail(name: String): SessionDetailUiState {
        val n = 1500
        val timeS = FloatArray(n) { it * 0.5f }
        fun angles(f: (Double) -> Double) = FloatArray(n) { f(timeS[it].toDouble()).toFloat() }
        val series = AngleSeries(
            timeS,
            angles { t -> ((40.0 + 0.4 * t + 30 * sin(t / 20)) + 180.0).mod(360.0) - 180.0 },
            angles { t -> 10 * sin(t / 7) - 5 },
            angles { t -> 25 * sin(t / 11) },
            originNs = 2_000_000_000L,
            markers = listOf(
                PlotMarker(2_000_000_000L + 60_000_000_000L, "leave home"),
                PlotMarker(2_000_000_000L + 300_000_000_000L, "crossing"),
                PlotMarker(2_000_000_000L + 700_000_000_000L, "platform"),
            ),
        )
        // Steady rates, a 20-s stall of the magnetometer, the game rotation vector slower at first.
        val rates = RateSeries(
            2_000_000_000L, 1.0,
            linkedMapOf(
                "accelerometer" to FloatArray(754) { 200f - (it % 3) },
                "gyroscope" to FloatArray(754) { 200f },
                "magnetometer" to FloatArray(754) { if (it in 300..320) 0f else 100f },
                "game_rotation_vector" to FloatArray(754) { if (it < 60) 50f else 99.6f },
            ),
        )
        return SessionDetailUiState(name, loading = false, summary = summary(name, 754, 200.0, 1_795_688_100_000L), angles = series, rates = rates)
    }
}
