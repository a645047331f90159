package dev.motionfusion.app.sessions

import dev.motionfusion.app.ui.PlotMarker
import dev.motionfusion.core.session.WakeLockUse
import java.io.File
import java.io.IOException

/** One raw stream of a session: rows and the achieved rate (rows over the stream's time span). */
internal data class StreamSummary(val name: String, val rows: Long, val rateHz: Double)

/** What the sessions list and detail show of a session. */
internal data class SessionSummary(
    val name: String,
    /** UTC start, ms since the epoch, from the session's wall-clock anchor; null if unknown. */
    val startWallClockMs: Long?,
    /** From the first to the last sensor timestamp, ns. */
    val durationNs: Long,
    /** Bytes on disk, all files of the session. */
    val sizeBytes: Long,
    val streams: List<StreamSummary>,
    val fusedRows: Long,
    val recovered: Boolean,
    /** The session this one continues after a killed recording resumed (meta.json `continues`), and the gap between them, ns. */
    val continues: String? = null,
    val gapNs: Long? = null,
    /** Made by the still-recording mode (meta.json `still_recording`): its noise model can be exported. */
    val stillRecording: Boolean = false,
    /** Whether the recording held the wake lock, and why (meta.json `wake_lock`); null in sessions that do not say. */
    val wakeLock: WakeLockUse? = null,
) {
    val totalRows: Long get() = streams.sumOf { it.rows }
}

/**
 * Android azimuth, pitch and roll of the fused orientation over time, in degrees, for plotting;
 * [timeS] in seconds after [originNs] (the session's sensor clock, ns: the clock of its markers).
 */
internal class AngleSeries(
    val timeS: FloatArray, val azimuthDeg: FloatArray, val pitchDeg: FloatArray, val rollDeg: FloatArray, val originNs: Long = 0L,
    /** The session's markers (markers.csv), timestamps on the sensor clock, drawn on the plot. */
    val markers: List<PlotMarker> = emptyList(),
) {
    val size: Int get() = timeS.size
}

/**
 * Events per second of each raw stream over a session, in bins of [binSeconds] starting at
 * [originNs] (the session's sensor clock); [ratesHz] per stream name, one value a bin. Bins are
 * 1 s unless the session is longer than the bins allowed, then 2, 4, … s (memory stays bounded).
 */
internal class RateSeries(val originNs: Long, val binSeconds: Double, val ratesHz: Map<String, FloatArray>) {
    val bins: Int get() = ratesHz.values.maxOfOrNull { it.size } ?: 0

    companion object {
        val EMPTY = RateSeries(0L, 1.0, emptyMap())
    }
}

/** Reading sessions for the screens; bound to the session format's reader in [CoreSessionLibrary]. */
internal interface SessionLibrary {
    @Throws(IOException::class)
    fun summary(dir: File): SessionSummary

    /** The fused orientation as angles, thinned to at most [maxPoints] points spread over the session, with the session's markers. */
    @Throws(IOException::class)
    fun angles(dir: File, maxPoints: Int): AngleSeries

    /** Each raw stream's events per second over time, at most [maxBins] bins per stream (see [RateSeries]). */
    @Throws(IOException::class)
    fun rates(dir: File, maxBins: Int): RateSeries
}
