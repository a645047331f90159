package dev.motionfusion.app.settings

import dev.motionfusion.app.sensor.SamplingRate
import dev.motionfusion.app.sensor.SensorStreams
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.filter.FilterMode
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.WorldFrame

/** How angles are shown. */
enum class AngleConvention {
    /**
     * Android's getOrientation: azimuth (0..360°, from magnetic north towards east, of the
     * screen's up direction), pitch (−90..90°, positive when the top edge tilts down), roll
     * (−180..180°, positive when the right edge tilts down: roll = atan2(−A_x, A_z) with A the
     * up direction in screen coordinates).
     */
    ANDROID,

    /**
     * Aerospace yaw, pitch, roll (intrinsic Z-Y-X) of the phone as a vehicle whose nose is the
     * screen's top edge, right wing the right edge, in North-East-Down: yaw 0..360° like azimuth,
     * pitch −90..90° positive nose up, roll −180..180° positive right edge down.
     */
    AEROSPACE,
}

/**
 * Everything the settings decide, validated: the whole [FilterSettings] (its own type checks
 * every value; the output frame stays ENU, the frame the app shows and records), the angle
 * convention, the requested sensor rate, the sensors a recording writes beside those the filter needs ([recordedStreams]), how long Record counts down before the recording starts and when a recording stops by itself. One object for the live filter, the recorder (its
 * meta.json) and the settings screen; [dev.motionfusion.app.settings.Setting] lists its values.
 */
data class LiveSettings(
    val filter: FilterSettings = DEFAULT_FILTER,
    val convention: AngleConvention = AngleConvention.ANDROID,
    val rate: SamplingRate = SamplingRate.Hz(100),
    val limits: RecordingLimits = RecordingLimits(),
    /** Record starts the recording after this many seconds, counted down on screen (0: at once). */
    val startDelayS: Int = 0,
    /** The optional streams ([OPTIONAL_STREAMS]) a recording writes; the filter's own are written whatever this says. */
    val optionalStreams: Set<SessionStream> = OPTIONAL_STREAMS,
) {
    init {
        require(optionalStreams.all { it in OPTIONAL_STREAMS }) { "not an optional stream: ${optionalStreams - OPTIONAL_STREAMS}" }
        require(startDelayS in 0..MAX_START_DELAY_S) { "start delay must be 0..$MAX_START_DELAY_S s, got $startDelayS" }
        require(filter.outputFrame == WorldFrame.ENU) { "the app's filter outputs device → ENU, got ${filter.outputFrame}" }
    }

    /** 6D or 9D, as requested (the capture falls back to 6D without magnetometer). */
    val mode: FilterMode get() = filter.mode

    /**
     * The streams a recording writes: those the filter's [mode] reads (accelerometer and gyroscope; the magnetometer in
     * 9D), those of a calibration the recording applies ([calibrated]: its uncalibrated streams, which the filter then
     * reads instead), and the chosen [optionalStreams]. A replay of the session can so run the filter as it ran.
     */
    fun recordedStreams(calibrated: Set<SessionStream> = emptySet()): Set<SessionStream> =
        REQUIRED_STREAMS + (if (mode == FilterMode.MARG) setOf(SessionStream.MAGNETOMETER) else emptySet()) + calibrated + optionalStreams

    companion object {
        val DEFAULT_FILTER = FilterSettings()

        /** Written by every recording: the filter reads them in either mode. */
        val REQUIRED_STREAMS: Set<SessionStream> = setOf(SessionStream.ACCELEROMETER, SessionStream.GYROSCOPE)

        /** The sensor streams a recording may leave out (all recorded by default); the magnetometer only in 6D. */
        val OPTIONAL_STREAMS: Set<SessionStream> = SensorStreams.all.toSet() - REQUIRED_STREAMS

        /** The start delays the settings offer, s (0: off). */
        val START_DELAY_CHOICES_S: List<Int> = listOf(0, 3, 10)
        const val MAX_START_DELAY_S = 60
    }
}
