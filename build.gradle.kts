// Root of the Android Studio project; see settings.gradle.kts. Versions: gradle/libs.versions.toml.

// The R8 of the release build is pinned in settings.gradle.kts (pluginManagement { buildscript { … } }).

plugins {
    alias(libs.plugins.android.application) apply false
    alias(libs.plugins.kotlin.android) apply false
    alias(libs.plugins.kotlin.jvm) apply false
}

allprojects {
    group = "dev.motionfusion"
    version = "0.1.0"
}
